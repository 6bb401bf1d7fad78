#include "prep/texture_buffers.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace pcl {
namespace {

uint32_t wrapCode(TextureWrap w) {
    switch (w) {
        case TextureWrap::Clamp: return PCL_WRAP_CLAMP;
        case TextureWrap::Mirror: return PCL_WRAP_MIRROR;
        case TextureWrap::Repeat: break;
    }
    return PCL_WRAP_REPEAT;
}

}  // namespace

PclTexture textureDescriptor(const Texture& texture, uint32_t offset) {
    PclTexture d{};
    d.offset = offset;
    d.width = uint32_t(texture.image.width);
    d.height = uint32_t(texture.image.height);
    d.wrap = wrapCode(texture.wrapU) | wrapCode(texture.wrapV) << 8;
    // T R S as KHR_texture_transform's GLSL writes it (column-major mat3s):
    // u' = cos r · su u − sin r · sv v + ou,  v' = sin r · su u + cos r · sv v + ov.
    const TextureTransform& t = texture.transform;
    const double c = std::cos(double(t.rotation)), s = std::sin(double(t.rotation));
    d.m[0] = float(c * t.scale[0]);
    d.m[1] = float(-s * t.scale[1]);
    d.m[2] = t.offset[0];
    d.m[3] = float(s * t.scale[0]);
    d.m[4] = float(c * t.scale[1]);
    d.m[5] = t.offset[1];
    if (t.rotation == 0.0f) {  // exact, so an unrotated transform is a pure scale and offset
        d.m[1] = d.m[3] = 0.0f;
        d.m[0] = t.scale[0];
        d.m[4] = t.scale[1];
    }
    d.texCoord = uint32_t(texture.texCoord);
    return d;
}

PclMaterialTextures materialTextureDescriptor(const Scene& scene, const Material& material,
                                              const std::vector<uint32_t>& offsets) {
    PclMaterialTextures d{};
    const int slots[PCL_TEXTURE_SLOTS] = {material.rhoDTexture, material.rhoSTexture, material.exponentTexture,
                                          material.emissionTexture};
    for (int k = 0; k < PCL_TEXTURE_SLOTS; ++k)
        if (slots[k] >= 0)
            d.slot[k] =
                textureDescriptor(scene.textures[size_t(slots[k])], offsets.empty() ? 0u : offsets[size_t(slots[k])]);
    d.exponentLo = material.exponentRange[0];
    d.exponentHi = material.exponentRange[1];
    const Material::MetallicRoughness& mr = material.metallicRoughness;
    d.mapping = mr.active ? PCL_TEXTURE_MAP_METALLIC_ROUGHNESS : PCL_TEXTURE_MAP_PHONG;
    for (int c = 0; c < 3; ++c) d.baseColor[c] = mr.baseColor[c];
    d.metallic = mr.metallic;
    d.roughness = mr.roughness;
    d.f0 = mr.f0;
    return d;
}

TextureBuffers buildTextureBuffers(const Scene& scene, const SceneGeometry& geometry) {
    TextureBuffers b;
    b.materialTextures.resize(scene.materials.size(), PclMaterialTextures{});
    if (!scene.hasTextures()) return b;

    // Each texture's texels once, in Scene::textures order.
    std::vector<uint32_t>& offsets = b.offsets;
    offsets.assign(scene.textures.size(), 0);
    for (size_t t = 0; t < scene.textures.size(); ++t) {
        const Image& image = scene.textures[t].image;
        if (b.texels.size() + image.rgb.size() > 0xFFFFFFFFull)
            throw InputError(scene.path + ": textures: " + std::to_string(b.texels.size() + image.rgb.size()) +
                             " texel floats in all: expected below 2^32");
        offsets[t] = uint32_t(b.texels.size());
        b.texels.insert(b.texels.end(), image.rgb.begin(), image.rgb.end());
    }
    for (size_t m = 0; m < scene.materials.size(); ++m)
        b.materialTextures[m] = materialTextureDescriptor(scene, scene.materials[m], offsets);

    b.triangleUvs.resize(geometry.triangleCount(), PclTriangleUv{});
    for (uint32_t prim = 0; prim < geometry.triangleCount(); ++prim) {
        const PrimitiveRef ref = geometry.primitive(prim);
        const TriangleMesh& mesh = scene.meshes[ref.object];
        const uint32_t* idx = &mesh.indices[3 * size_t(ref.index)];
        for (int set = 0; set < 2; ++set) {
            if (mesh.uv[set].empty()) continue;
            for (int k = 0; k < 3; ++k) {
                b.triangleUvs[prim].uv[set][2 * k] = mesh.uv[set][2 * size_t(idx[k])];
                b.triangleUvs[prim].uv[set][2 * k + 1] = mesh.uv[set][2 * size_t(idx[k]) + 1];
            }
        }
    }
    return b;
}

}  // namespace pcl
