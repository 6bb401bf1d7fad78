// The flat scene buffers every photon-pass stage reads, kernel and twin alike
// (kernels/README.md, "Flat scene buffers"): materials, per-primitive shading data, and one
// light entry per point/spot/directional light and per emitting triangle.
#pragma once
#include <cstdint>
#include <vector>

#include "geometry/scene_geometry.h"
#include "prep/environment_buffers.h"
#include "prep/normal_map_buffers.h"
#include "prep/shading_normals.h"
#include "prep/texture_buffers.h"
#include "scene/scene.h"
#include "shared/types.h"

namespace pcl {

struct SceneBuffers {
    std::vector<PclMaterial> materials;
    std::vector<PclPrimInfo> primInfo;  // by global primitive id
    std::vector<PclLight> lights;       // projFirst/projCount are 0 until projection maps are built
    std::vector<uint32_t> projCells;    // marked projection-map cells, per light [projFirst, +projCount)
    // Participating media, filled only when the scene has one (hasMedia): the medium table, the
    // medium on either side of every primitive (prep/medium_boundaries) and the medium each light
    // entry emits into (PCL_NO_MEDIUM: vacuum).
    bool hasMedia = false;
    std::vector<PclMedium> media;
    std::vector<PclPrimMedium> primMedia;  // by global primitive id
    std::vector<int32_t> lightMedia;       // by light entry (PCL_MEDIUM_UNREACHABLE: directional in fog)
    int32_t cameraMedium = PCL_NO_MEDIUM;  // the medium at the camera position (the eye rays start in it)
    Vec3 sceneCentre{0.0f};                // bounding sphere of the geometry over the shutter
    float sceneRadius = 0.0f;
    TextureBuffers textures;  // ρd textures (prep/texture_buffers.h); descriptors of width 0 without
    // Vertex normals of the smooth triangles (prep/shading_normals.h); empty when none is smooth.
    std::vector<PclTriangleNormals> triangleNormals;
    NormalMapBuffers normalMaps;  // prep/normal_map_buffers.h; empty when no material has a normal map
    float rayEpsilon = 1e-6f;     // spawn offset: 1e-4 of the bounds' diagonal, at least 1e-6
    bool hasMotion = false;
    // The sky (prep/environment_buffers): its tables, and its photon light entry, the last of
    // lights, when the scene has one.
    EnvironmentBuffers sky;
};

SceneBuffers buildSceneBuffers(const Scene& scene, const SceneGeometry& geometry);

}  // namespace pcl
