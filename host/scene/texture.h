// Image textures of the scene model: a linear RGB image with its sampler (wrap modes) and a
// KHR_texture_transform, as a material refers to it. kernels/shared/texture.h samples the
// packed form (prep/texture_buffers.h) on the device and in the CPU twin alike.
#pragma once
#include <string>

#include "image/image.h"

namespace pcl {

enum class TextureWrap { Repeat, Clamp, Mirror };

// KHR_texture_transform: uv' = T(offset) R(rotation) S(scale) uv, rotation in radians
// counter-clockwise (the extension's GLSL: u' = cos r su − sin r sv + ou, v' = sin r su + cos r sv + ov).
struct TextureTransform {
    float offset[2] = {0.0f, 0.0f};
    float scale[2] = {1.0f, 1.0f};
    float rotation = 0.0f;
    bool identity() const {
        return offset[0] == 0.0f && offset[1] == 0.0f && scale[0] == 1.0f && scale[1] == 1.0f && rotation == 0.0f;
    }
};

// One use of an image as a texture. Texture coordinates: (0, 0) is the image's top-left corner,
// u runs right, v down (glTF's convention); texel (i, j) covers [i, i+1)/W × [j, j+1)/H and is
// filtered bilinearly.
struct Texture {
    std::string path;  // the file it came from
    Image image;       // linear RGB, every texel in [0, 1] (the loaders check)
    TextureWrap wrapU = TextureWrap::Repeat, wrapV = TextureWrap::Repeat;
    TextureTransform transform;
    int texCoord = 0;  // the mesh's texture coordinate set (0 or 1)
};

}  // namespace pcl
