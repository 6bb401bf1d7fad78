// Collapse a binary SAH tree into 8-wide nodes and flatten it into the arrays the kernels read
// (kernels/shared/types.h): every wide node pulls up the binary descendants with the largest
// surface area until it has eight children (Wald et al. 2008, "Getting Rid of Packets"), leaves
// become runs of 4-triangle packets or runs of spheres.
#pragma once
#include <functional>
#include <vector>

#include "geometry/bvh_build.h"
#include "shared/types.h"

namespace pcl {

struct BvhStats;

// Where the collapse reads primitive data, by global primitive id.
struct CollapseSource {
    const std::vector<Bounds3>* boxes = nullptr;  // per primitive, over the shutter interval
    uint32_t triangleCount = 0;
    float traversalCost = 1.0f;  // BvhStats::sahCost: cost of a wide node visit, in packet tests
    // Triangle: vertex 0 and the two edges, and its motion; packets group lanes by motion.
    std::function<void(uint32_t prim, Vec3& v0, Vec3& e1, Vec3& e2, Vec3& motion)> triangle;
    std::function<PclSphere(uint32_t prim)> sphere;
};

// Fills nodes/packets/spheres (cleared first) and the tree figures in stats. The root is
// always node 0 and always an interior node: an empty scene gets a root with eight empty
// slots, a one-leaf tree a root with one leaf slot, so traversal has no special cases.
//
// stats.maxStack is the most entries the traversal stack holds for any ray, assuming the
// traversal pushes every child whose box is hit and then pops the nearest:
//   S(node) = max(c, c - 1 + max over children S(child)),  S(leaf) = 0.
void collapseBvh(const BinaryBvh& bvh, const CollapseSource& source, std::vector<PclBvhNode>& nodes,
                 std::vector<PclTriPacket>& packets, std::vector<PclSphere>& spheres, BvhStats& stats);

}  // namespace pcl
