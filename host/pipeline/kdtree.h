// Jensen's left-balanced kd-tree built on the device (kernels/kdtree.cl; kernels/README.md,
// "Photon maps", kd-tree): level by level, each level one radix sort of all photons by
// (subtree, rank on the subtree's split axis) — the rank being the photon's place in the map
// ordered by (coordinate key, photon index), from one stable radix sort per axis up front, so
// the order is the README's (subtree << 32 | coordinate key, stable) in fewer bits; keys are
// 32-bit while ⌈log2 n⌉ + level bits fit. Once a level's subtrees hold at most finishSize
// photons, one work-item per subtree finishes it. The result is the photon array in heap
// order (node h's children at 2h+1, 2h+2) with each node's split axis in bits 27..28 of
// `packed`, and index[h] = the map position of the photon at node h. The twin is
// host/reference/kdtree.h; both give the same tree byte for byte.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "device/device.h"
#include "shared/types.h"

namespace pcl {

struct DeviceKdTree {
    cl::Buffer photons;  // PclPhoton[count], heap order, axis bits set
    cl::Buffer index;    // uint32[count]: heap position → photon index in the input map
    size_t count = 0;
    uint32_t levels = 0;        // ⌊log2 count⌋ + 1 (0 for an empty map)
    uint32_t sortedLevels = 0;  // levels built by a radix sort (the rest by kdtree_finish)
};

struct KdTreeTiming {
    double sortSeconds = 0.0;   // device time in the radix sorts
    double otherSeconds = 0.0;  // device time in the kd-tree kernels
};

// Builds the tree of the first n photons of `photons` (left untouched). n < 2^31.
// finishSize: once a level's subtrees hold at most this many photons, one work-item finishes
// each (kdtree_finish) instead of sorting the remaining levels; -1: the device's default (128 on
// CPUs, 32 on GPUs), 0: every level sorted. The tree is the same either way.
DeviceKdTree buildKdTree(Device& device, const cl::Buffer& photons, size_t n, KdTreeTiming* timing = nullptr,
                         int finishSize = -1);

// The memory plan's view of a build (buildKdTree's own loop, replayed): the finishSize -1
// stands for on a device of this type, and whether a level of a tree of n photons needs 64-bit
// sort keys (and so a second, 64-bit sort workspace).
int kdTreeFinishSize(cl_device_type type);
bool kdTreeUses64BitKeys(size_t n, int finishSize);

}  // namespace pcl
