// SceneGeometry::build: gather primitive bounds from the scene, build the binary SAH tree,
// collapse it to 8-wide nodes and flatten it (bvh_build.cpp, bvh_collapse.cpp).
#include "geometry/scene_geometry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "core/clock.h"
#include "core/error.h"
#include "geometry/bvh_build.h"
#include "geometry/bvh_collapse.h"

namespace pcl {
namespace {

// Moving primitives are tested with the ray origin shifted by -motion·τ, while their box is
// tested with the unshifted ray; the two roundings differ by a few ulps of the coordinates, so
// such boxes (and sphere boxes, whose c ± r is rounded) are padded by a relative epsilon.
void pad(Bounds3& b, float scale) {
    float e = 1e-6f * scale;
    b.lo -= Vec3(e);
    b.hi += Vec3(e);
}
float magnitude(const Bounds3& b) { return std::max(maxComponent(vmax(vmax(b.lo, -b.lo), vmax(b.hi, -b.hi))), 1e-30f); }

}  // namespace

size_t BvhStats::bytes() const {
    return nodes * sizeof(PclBvhNode) + packets * sizeof(PclTriPacket) + spheres * sizeof(PclSphere);
}

double BvhStats::bytesPerTriangle() const {
    if (triangles == 0) return 0.0;
    return double(nodes * sizeof(PclBvhNode) + packets * sizeof(PclTriPacket)) / double(triangles);
}

SceneGeometry SceneGeometry::build(const Scene& scene, const BvhBuildOptions& options) {
    auto start = std::chrono::steady_clock::now();
    SceneGeometry g;
    g.meshFirstTriangle_.reserve(scene.meshes.size());
    uint32_t triangles = 0;
    for (const auto& m : scene.meshes) {
        g.meshFirstTriangle_.push_back(triangles);
        triangles += static_cast<uint32_t>(m.triangleCount());
    }
    g.triangleCount_ = triangles;
    const uint32_t total = triangles + static_cast<uint32_t>(scene.spheres.size());
    // A leaf word addresses its first packet or sphere with 26 bits (types.h); a triangle needs
    // at most one packet, so this bound keeps every index representable.
    if (total > PCL_CHILD_INDEX_MASK)
        throw InputError(scene.path + ": scene: expected at most " + std::to_string(PCL_CHILD_INDEX_MASK) +
                         " primitives (the BVH layout's limit), got " + std::to_string(total));

    // Per-primitive data by global id: bounds over the shutter, and what a packet lane needs.
    std::vector<Bounds3> boxes(total);
    std::vector<uint32_t> triMesh(triangles);
    for (size_t mi = 0; mi < scene.meshes.size(); ++mi) {
        const auto& m = scene.meshes[mi];
        const bool moving = !(m.motion == Vec3(0.0f));
        const uint32_t base = g.meshFirstTriangle_[mi];
        for (size_t t = 0; t < m.triangleCount(); ++t) {
            Bounds3 b;
            for (int k = 0; k < 3; ++k) {
                Vec3 p = m.positions[m.indices[3 * t + k]];
                b.extend(p);
                if (moving) b.extend(p + m.motion);
            }
            if (moving) pad(b, magnitude(b) + maxComponent(vmax(m.motion, -m.motion)));
            boxes[base + t] = b;
            triMesh[base + t] = static_cast<uint32_t>(mi);
        }
    }
    for (size_t si = 0; si < scene.spheres.size(); ++si) {
        const auto& s = scene.spheres[si];
        Bounds3 b;
        b.extend(s.centre - Vec3(s.radius));
        b.extend(s.centre + Vec3(s.radius));
        b.extend(s.centre + s.motion - Vec3(s.radius));
        b.extend(s.centre + s.motion + Vec3(s.radius));
        pad(b, magnitude(b) + maxComponent(vmax(s.motion, -s.motion)));
        boxes[triangles + si] = b;
    }
    for (const auto& b : boxes)
        if (isFinite(b.lo) && isFinite(b.hi)) g.bounds_.extend(b);

    BinaryBvh bvh = buildBinaryBvh(boxes, triangles, options);

    CollapseSource src;
    src.boxes = &boxes;
    src.triangleCount = triangles;
    src.triangle = [&](uint32_t prim, Vec3& v0, Vec3& e1, Vec3& e2, Vec3& motion) {
        const auto& m = scene.meshes[triMesh[prim]];
        const size_t t = prim - g.meshFirstTriangle_[triMesh[prim]];
        Vec3 p0 = m.positions[m.indices[3 * t]];
        Vec3 p1 = m.positions[m.indices[3 * t + 1]];
        Vec3 p2 = m.positions[m.indices[3 * t + 2]];
        v0 = p0;
        e1 = p1 - p0;
        e2 = p2 - p0;
        motion = m.motion;
    };
    src.sphere = [&](uint32_t prim) {
        const auto& s = scene.spheres[prim - triangles];
        PclSphere out{};
        out.cx = s.centre.x;
        out.cy = s.centre.y;
        out.cz = s.centre.z;
        out.radius = s.radius;
        out.mx = s.motion.x;
        out.my = s.motion.y;
        out.mz = s.motion.z;
        out.prim = prim;
        return out;
    };
    collapseBvh(bvh, src, g.nodes, g.packets, g.spheres, g.stats_);
    g.stats_.binaryDepth = bvh.depth;
    g.stats_.buildSeconds = since(start);
    return g;
}

PrimitiveRef SceneGeometry::primitive(uint32_t prim) const {
    if (prim >= triangleCount_) return {PrimitiveRef::Sphere, prim - triangleCount_, 0};
    // The last mesh whose first triangle is <= prim (empty meshes share a first index).
    auto it = std::upper_bound(meshFirstTriangle_.begin(), meshFirstTriangle_.end(), prim);
    auto mesh = static_cast<uint32_t>(it - meshFirstTriangle_.begin()) - 1;
    return {PrimitiveRef::Triangle, mesh, prim - meshFirstTriangle_[mesh]};
}

}  // namespace pcl
