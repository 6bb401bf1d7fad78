// Reading an image file as a texture: the checks every loader applies (readable, 1, 3 or 4
// channels, at least 1x1, texels in [0,1] once linear) with the usual "FILE: FIELD: expected X,
// got Y" message, and the sRGB decoding of display-encoded files.
#pragma once
#include <string>
#include <vector>

#include "image/image.h"

namespace pcl {

// How the file's values encode light: sRGB (IEC 61966-2-1) or linear. Auto: sRGB for integer
// formats (8/16-bit PNG, JPEG, ...), linear for float ones (EXR, HDR, PFM).
enum class TextureEncoding { Auto, Srgb, Linear };

// The linear RGB texels of `imagePath` (grey replicated to RGB, alpha dropped), refused through
// failInput(sceneFile, field, ...) when it is missing, unreadable, 0x0, has 2 or more than 4
// channels, or a texel outside [0, 1] (a reflectance above 1 would create energy).
Image loadTextureImage(const std::string& sceneFile, const std::string& field, const std::string& imagePath,
                       TextureEncoding encoding);

// The same for an image embedded in the scene file (a glTF bufferView or data: URI): its encoded
// bytes and MIME type (image/png or image/jpeg, glTF's two; anything else is refused).
Image loadEmbeddedTextureImage(const std::string& sceneFile, const std::string& field,
                               const std::vector<unsigned char>& bytes, const std::string& mimeType,
                               TextureEncoding encoding);

// The sRGB decoding of one encoded value in [0, 1] (IEC 61966-2-1).
float srgbToLinear(float encoded);

}  // namespace pcl
