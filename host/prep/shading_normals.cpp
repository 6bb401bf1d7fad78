#include "prep/shading_normals.h"

#include <cmath>

namespace pcl {
namespace {

// 1 − cos of the largest angle between a vertex normal and the face normal that still counts as
// flat: ~0.08°, far below anything a mesh's smoothing means, far above float rounding.
constexpr float kFlatTolerance = 1e-6f;

}  // namespace

std::vector<PclTriangleNormals> buildTriangleNormals(const Scene& scene, const SceneGeometry& geometry) {
    std::vector<PclTriangleNormals> out;
    bool anySmooth = false;
    for (uint32_t prim = 0; prim < geometry.triangleCount(); ++prim) {
        const PrimitiveRef ref = geometry.primitive(prim);
        const TriangleMesh& mesh = scene.meshes[ref.object];
        if (mesh.normals.empty()) continue;
        const uint32_t* idx = &mesh.indices[3 * size_t(ref.index)];
        const Vec3 p0 = mesh.positions[idx[0]], p1 = mesh.positions[idx[1]], p2 = mesh.positions[idx[2]];
        const Vec3 c = cross(p1 - p0, p2 - p0);
        const float area2 = length(c);
        if (!(area2 > 0.0f)) continue;
        const Vec3 ng = c / area2;
        bool smooth = false;
        for (int k = 0; k < 3; ++k) {
            const Vec3 nv = mesh.normals[idx[k]];
            const float len = length(nv);
            smooth = smooth || !(len > 0.0f) || std::fabs(dot(nv, ng)) / len < 1.0f - kFlatTolerance;
        }
        if (!smooth) continue;
        if (!anySmooth) out.assign(geometry.triangleCount(), PclTriangleNormals{});
        anySmooth = true;
        for (int k = 0; k < 3; ++k) {
            const Vec3 nv = mesh.normals[idx[k]];
            out[prim].n[3 * k] = nv.x;
            out[prim].n[3 * k + 1] = nv.y;
            out[prim].n[3 * k + 2] = nv.z;
        }
    }
    return out;
}

}  // namespace pcl
