// The scene's normal maps as the kernels and the CPU twin read them (kernels/shared/shading_frame.h):
// one PclNormalMap per material (width 0: none; its texels in TextureBuffers::texels with the other
// textures) and the vertex tangents of every triangle (TriangleMesh::tangents, per corner).
// Kept apart from the ρd textures (TextureBuffers::materialTextures) so each kind of map has its
// own descriptor array.
#pragma once
#include <vector>

#include "geometry/scene_geometry.h"
#include "prep/texture_buffers.h"
#include "scene/scene.h"
#include "shared/types.h"

namespace pcl {

struct NormalMapBuffers {
    std::vector<PclNormalMap> maps;                     // by material; empty when no material has a map
    std::vector<PclTriangleTangents> triangleTangents;  // by global primitive id below triangleCount
    bool mapped() const { return !maps.empty(); }
};

// Empty when no material has a normal map. A mesh of a normal-mapped material must carry tangents
// (addMissingTangents, scene/mesh_tangents.h; validateScene adds them): InternalError otherwise.
NormalMapBuffers buildNormalMapBuffers(const Scene& scene, const SceneGeometry& geometry,
                                       const TextureBuffers& textures);

}  // namespace pcl
