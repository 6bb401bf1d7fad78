#include "prep/normal_map_buffers.h"

#include <string>

#include "core/error.h"

namespace pcl {

NormalMapBuffers buildNormalMapBuffers(const Scene& scene, const SceneGeometry& geometry,
                                       const TextureBuffers& textures) {
    NormalMapBuffers b;
    bool any = false;
    for (const Material& m : scene.materials) any = any || m.normalTexture >= 0;
    if (!any) return b;
    b.maps.resize(scene.materials.size(), PclNormalMap{});
    for (size_t m = 0; m < scene.materials.size(); ++m) {
        const int t = scene.materials[m].normalTexture;
        if (t < 0) continue;
        b.maps[m].texture = textureDescriptor(scene.textures[size_t(t)], textures.offsets[size_t(t)]);
        b.maps[m].scale = scene.materials[m].normalScale;
    }
    b.triangleTangents.resize(geometry.triangleCount(), PclTriangleTangents{});
    for (uint32_t prim = 0; prim < geometry.triangleCount(); ++prim) {
        const PrimitiveRef ref = geometry.primitive(prim);
        const TriangleMesh& mesh = scene.meshes[ref.object];
        if (mesh.material < 0 || scene.materials[size_t(mesh.material)].normalTexture < 0) continue;
        if (mesh.tangents.size() != 4 * mesh.positions.size())
            throw InternalError("normal maps: mesh \"" + mesh.name + "\" has " +
                                std::to_string(mesh.tangents.size() / 4) + " tangents for " +
                                std::to_string(mesh.positions.size()) +
                                " vertices (expected one each: addMissingTangents)");
        const uint32_t* idx = &mesh.indices[3 * size_t(ref.index)];
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 4; ++c) b.triangleTangents[prim].t[4 * k + c] = mesh.tangents[4 * size_t(idx[k]) + c];
    }
    return b;
}

}  // namespace pcl
