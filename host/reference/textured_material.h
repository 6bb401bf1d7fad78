// The twin's material at a hit: the flat PclMaterial of the hit primitive with its textured
// quantities (ρd, ρs, the exponent) at the hit point, sampled and mapped by the same shared
// functions the kernels use (kernels/shared/texture.h).
#pragma once
#include <cstdint>

#include "prep/scene_buffers.h"
#include "shared/texture.h"

namespace pcl {

inline PclMaterial texturedMaterial(const SceneBuffers& b, uint32_t triangleCount, const PclHit& hit) {
    const uint32_t mat = b.primInfo[hit.prim].material;
    PclMaterial m = b.materials[mat];
    if (mat >= b.textures.materialTextures.size()) return m;  // buffers made without buildTextureBuffers
    texture_material_at(b.textures.materialTextures.data(), b.textures.texels.data(), b.textures.triangleUvs.data(),
                        mat, hit.prim, triangleCount, hit.u, hit.v, &m);
    return m;
}

}  // namespace pcl
