// SceneGeometry: the scene's triangles and spheres in a binned-SAH BVH collapsed to 8-wide
// nodes, flattened into exactly the arrays kernels read (kernels/shared/types.h), plus the
// host traversal that the CPU twin and the reference path tracer use.
#pragma once
#include <cstdint>
#include <vector>

#include "scene/scene.h"
#include "shared/types.h"

namespace pcl {

struct BvhBuildOptions {
    int bins = 16;             // SAH bins per axis (>= 12)
    int maxLeafTriangles = 4;  // triangles per leaf before SAH may stop splitting
    // Binary SAH: cost of a binary node visit relative to one packet (or sphere) test. Below 1
    // because the collapse folds about three binary levels into one 8-wide node visit; 0.5
    // splits small leaves the wide root can hold for free (cornell-spheres: one leaf of 3
    // packets + 2 spheres at 1.0, ~20 % slower to trace).
    float traversalCost = 0.5f;
};

struct BvhStats {
    size_t nodes = 0, packets = 0, spheres = 0, leaves = 0;
    size_t triangles = 0;  // triangles in the tree (packet lanes in use)
    double sahCost = 0.0;  // SAH cost of the 8-wide tree: Σ A/A_root over nodes (visit = 1)
                           // + Σ A/A_root × items over leaves (packet or sphere test = 1)
    double buildSeconds = 0.0;
    int binaryDepth = 0;              // depth of the binary SAH tree before collapsing
    int depth = 0;                    // depth of the 8-wide tree (root = 1)
    int maxStack = 0;                 // deepest traversal stack any ray can need (see bvh_collapse.h)
    size_t bytes() const;             // nodes + packets + spheres arrays
    double bytesPerTriangle() const;  // (nodes + packets) bytes / triangles
};

// Global primitive ids: triangles first (mesh by mesh, in file order), then spheres.
struct PrimitiveRef {
    enum Kind : uint8_t { Triangle, Sphere } kind;
    uint32_t object;  // mesh index or sphere index in Scene
    uint32_t index;   // triangle index within the mesh (0 for spheres)
};

class SceneGeometry {
public:
    static SceneGeometry build(const Scene& scene, const BvhBuildOptions& options = {});

    // Closest hit in (ray.tmin, ray.tmax); fills hit and returns true, or returns false and
    // sets hit.prim = PCL_NO_HIT. Moving primitives are placed at ray.time.
    bool intersect(const PclRay& ray, PclHit& hit) const;
    // Any hit in (ray.tmin, ray.tmax): shadow rays.
    bool occluded(const PclRay& ray) const;

    PrimitiveRef primitive(uint32_t prim) const;
    uint32_t triangleCount() const { return triangleCount_; }
    uint32_t primitiveCount() const { return triangleCount_ + static_cast<uint32_t>(spheres.size()); }
    Bounds3 bounds() const { return bounds_; }  // over the whole shutter interval
    const BvhStats& stats() const { return stats_; }

    // The flat arrays, uploaded as they are to the device.
    std::vector<PclBvhNode> nodes;
    std::vector<PclTriPacket> packets;
    std::vector<PclSphere> spheres;

private:
    std::vector<uint32_t> meshFirstTriangle_;  // prefix sums: global id of each mesh's first triangle
    uint32_t triangleCount_ = 0;
    Bounds3 bounds_;
    BvhStats stats_;
};

}  // namespace pcl
