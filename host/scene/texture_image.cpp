#include "scene/texture_image.h"

#include <cmath>
#include <filesystem>

#include "image/image_io.h"
#include "scene/scene_error.h"

namespace pcl {

float srgbToLinear(float e) { return e <= 0.04045f ? e / 12.92f : std::pow((e + 0.055f) / 1.055f, 2.4f); }

namespace {

// The checks and decoding every texture gets once its file is read; `shown` names it in messages.
Image textureFromStored(const std::string& sceneFile, const std::string& field, const std::string& shown,
                        const StoredImage& stored, TextureEncoding encoding) {
    if (stored.width < 1 || stored.height < 1)
        failInput(sceneFile, field, "an image of at least 1x1 texels",
                  shown + " of " + std::to_string(stored.width) + "x" + std::to_string(stored.height));
    const int n = stored.channels;
    if (n != 1 && n != 3 && n != 4)
        failInput(sceneFile, field, "an image with 1 (grey), 3 (RGB) or 4 (RGBA) channels",
                  shown + " with " + std::to_string(n));
    const bool srgb = encoding == TextureEncoding::Srgb || (encoding == TextureEncoding::Auto && stored.integer);
    Image image(stored.width, stored.height);
    for (size_t i = 0; i < image.pixelCount(); ++i)
        for (int c = 0; c < 3; ++c) {
            const float x = stored.pixels[i * size_t(n) + size_t(n >= 3 ? c : 0)];
            if (!std::isfinite(x) || x < 0.0f || x > 1.0f)
                failInput(sceneFile, field, "texels in [0, 1] (a reflectance)",
                          shown + ": " + std::to_string(x) + " at texel (" + std::to_string(i % size_t(image.width)) +
                              ", " + std::to_string(i / size_t(image.width)) + ")");
            image.rgb[3 * i + size_t(c)] = srgb ? srgbToLinear(x) : x;
        }
    return image;
}

}  // namespace

Image loadTextureImage(const std::string& sceneFile, const std::string& field, const std::string& imagePath,
                       TextureEncoding encoding) {
    const std::string shown = "\"" + imagePath + "\"";
    if (!std::filesystem::is_regular_file(imagePath))
        failInput(sceneFile, field, "an image file", shown + " (no such file)");
    StoredImage stored;
    try {
        stored = readStoredImage(imagePath);
    } catch (const std::exception& e) {
        failInput(sceneFile, field, "a readable image of at least 1x1 texels", shown + " (" + e.what() + ")");
    }
    return textureFromStored(sceneFile, field, shown, stored, encoding);
}

Image loadEmbeddedTextureImage(const std::string& sceneFile, const std::string& field,
                               const std::vector<unsigned char>& bytes, const std::string& mimeType,
                               TextureEncoding encoding) {
    const std::string shown = "an embedded " + mimeType + " of " + std::to_string(bytes.size()) + " bytes";
    const char* name = mimeType == "image/png" ? "embedded.png" : mimeType == "image/jpeg" ? "embedded.jpg" : nullptr;
    if (!name) failInput(sceneFile, field, "an embedded image/png or image/jpeg (glTF's image types)", shown);
    StoredImage stored;
    try {
        stored = readStoredImage(bytes, name);
    } catch (const std::exception& e) {
        failInput(sceneFile, field, "a readable image of at least 1x1 texels", shown + " (" + e.what() + ")");
    }
    return textureFromStored(sceneFile, field, shown, stored, encoding);
}

}  // namespace pcl
