// The scene's textures as the kernels and the CPU twin read them (kernels/shared/texture.h):
// every texture's texels packed one after another in one float buffer, one PclMaterialTextures
// per material (its texture slots, width 0: the quantity is the constant, and the mapping's
// factors), and the texture coordinates of every triangle.
//
// Floats (12 bytes a texel) rather than half or 8-bit: the texels are the loaders' linear values
// exactly, so the device, the twin and the tests' expectations agree to the last bit, and a
// lookup needs no decoding; an 8-bit sRGB texel would need a decode per lookup and half floats a
// conversion the host does not have. A 2048² texture takes 48 MiB (the memory plan counts it).
#pragma once
#include <cstdint>
#include <vector>

#include "geometry/scene_geometry.h"
#include "scene/scene.h"
#include "shared/types.h"

namespace pcl {

struct TextureBuffers {
    std::vector<PclMaterialTextures> materialTextures;  // by material: its texture slots and mapping
    std::vector<float> texels;                          // linear RGB, three floats a texel
    std::vector<PclTriangleUv> triangleUvs;             // by global primitive id below triangleCount
    std::vector<uint32_t> offsets;                      // by Scene::textures index: its first float in texels
    bool textured() const { return !texels.empty(); }
};

// One PclTexture for `texture` whose texels start at float `offset`: wrap modes and the
// KHR_texture_transform as a 2x3 matrix.
PclTexture textureDescriptor(const Texture& texture, uint32_t offset);

// The PclMaterialTextures of `material`: its slots' descriptors (texture t's texels at float
// offsets[t]; every offset 0 when `offsets` is empty, for a lookup in the texture's own image)
// and the mapping with its factors.
PclMaterialTextures materialTextureDescriptor(const Scene& scene, const Material& material,
                                              const std::vector<uint32_t>& offsets);

// Empty texels and coordinates in a scene without textures (the kernels then read only the
// materials' zero-width descriptors).
TextureBuffers buildTextureBuffers(const Scene& scene, const SceneGeometry& geometry);

}  // namespace pcl
