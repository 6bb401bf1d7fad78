// Binary BVH by binned SAH (Wald 2007, "On fast Construction of SAH-based Bounding Volume
// Hierarchies"), the first of three steps: build binary → collapse to 8-wide → flatten.
// Primitive ids below triangleCount are triangles (tested four at a time, so their SAH cost is
// counted per packet of 4), the rest are spheres.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "core/vec3.h"

namespace pcl {

struct BvhBuildOptions;

// Most primitives a binary leaf may hold: the wide node's leaf word counts up to 16 items.
constexpr uint32_t kMaxLeafPrimitives = 16;

struct BinaryNode {
    Bounds3 box;
    std::unique_ptr<BinaryNode> child[2];  // both set (interior) or both null (leaf)
    uint32_t first = 0, count = 0;         // leaf: range in BinaryBvh::order
    bool leaf() const { return !child[0]; }
};

struct BinaryBvh {
    std::unique_ptr<BinaryNode> root;  // null for an empty scene
    std::vector<uint32_t> order;       // primitive ids, leaf ranges contiguous
    int depth = 0;
};

// boxes[i] bounds primitive i over the whole shutter interval. A box that is not finite (a
// primitive with NaN coordinates: loaders drop those, but the builder must not crash) is binned
// at its clamped centroid and still referenced exactly once.
BinaryBvh buildBinaryBvh(const std::vector<Bounds3>& boxes, uint32_t triangleCount, const BvhBuildOptions& options);

// SAH leaf cost in units of one packet test: triangles in packets of 4, spheres one each.
inline float leafCost(uint32_t triangles, uint32_t spheres) {
    return static_cast<float>((triangles + 3) / 4 + spheres);
}

}  // namespace pcl
