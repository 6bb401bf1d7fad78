// CPU twin of the kd-tree build (kernels/README.md, "Photon maps", kd-tree): Jensen's
// left-balanced kd-tree (Jensen 2001 §6.3, "Realistic Image Synthesis Using Photon Mapping"
// appendix B) by plain recursion. For a subtree of n photons: the split axis is the axis of
// largest bounding-box extent (ties x, y, z); the photons are ordered by (flipped coordinate
// key, photon index) and the one at the left-balanced median position left(n) becomes the node,
// the `left` before it the left subtree (heap child 2h+1), the rest the right (2h+2).
#pragma once
#include <cstdint>
#include <vector>

#include "shared/types.h"

namespace pcl {

struct ReferenceKdTree {
    std::vector<PclPhoton> photons;  // heap order, split axis in bits 27..28 of packed
    std::vector<uint32_t> index;     // heap position → photon index in the input
};

ReferenceKdTree referenceBuildKdTree(const std::vector<PclPhoton>& photons);

// The size of the left subtree of a left-balanced (complete) tree of n nodes: with
// h = ⌊log2 n⌋, 2^(h−1) − 1 + min(2^(h−1), n − (2^h − 1)); 0 for n ≤ 1.
uint32_t referenceKdLeftSize(uint32_t n);

}  // namespace pcl
