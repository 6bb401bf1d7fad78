// glTF 2.0 (.gltf with embedded or side-by-side buffers, .glb) → Scene, through tinygltf.
// The material and light mapping is documented in scenes/README.md. Compiled only with
// PHOTONCL_WITH_GLTF (the lent GPU machine has no tinygltf); without it these functions are absent
// and the JSON loader refuses glTF references with a clear message.
#pragma once
#include <string>
#include <vector>

#include "scene/scene.h"
#include "scene/transform.h"

namespace pcl {

struct GltfImportOptions {
    Transform transform;        // applied on top of the file's node hierarchy
    bool geometryOnly = false;  // a JSON "mesh" shape: meshes (and their materials) only
    int materialOverride = -1;  // index into Scene::materials used for every primitive, or -1
    Vec3 motion{0.0f};          // given to every imported mesh
};

struct GltfImportResult {
    bool hasCamera = false;  // the file's first camera (in node order) was found
    Camera camera;
    size_t meshCount = 0;  // TriangleMeshes added
};

// Adds the file's meshes, materials and (unless geometryOnly) lights to `scene`.
GltfImportResult importGltf(Scene& scene, const std::string& path, const GltfImportOptions& options);

// The same from bytes already in memory; `path` names the file in messages and is the base for
// external buffers. Used by the fuzz harness.
GltfImportResult importGltfFromMemory(Scene& scene, const std::vector<unsigned char>& bytes, const std::string& path,
                                      const GltfImportOptions& options);

// A whole scene from one glTF file; its first camera is required. Not yet validated.
Scene loadGltfScene(const std::string& path);

}  // namespace pcl
