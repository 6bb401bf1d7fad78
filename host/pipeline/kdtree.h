// Jensen's left-balanced kd-tree built on the device (kernels/kdtree.cl; kernels/README.md,
// "Photon maps", kd-tree): one stable radix sort per axis up front gives three lists of the
// photons, each ordered by (coordinate key on its axis, photon index); each subtree's photons
// then occupy one range of all three lists, and splitting it is a stable partition of the lists
// into [left | node | right], which keeps them ordered: no level sorts. Large subtrees are split
// a level at a time by chunks (a count pass and a scatter pass); once a level's subtrees hold at
// most finishSize photons, one work-item per subtree finishes it by sequential partitions. The
// result is the photon array in heap order (node h's children at 2h+1, 2h+2) with each node's
// split axis in bits 27..28 of `packed`, and index[h] = the map position of the photon at node
// h. The twin is host/reference/kdtree.h; both give the same tree byte for byte.
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
    uint32_t sortedLevels = 0;  // levels split a level at a time (count and scatter; the rest by kdtree_finish)
};

struct KdTreeTiming {
    double sortSeconds = 0.0;   // device time in the radix sorts
    double otherSeconds = 0.0;  // device time in the kd-tree kernels
};

// Builds the tree of the first n photons of `photons` (left untouched). n < 2^31.
// finishSize: once a level's subtrees hold at most this many photons, one work-item finishes
// each (kdtree_finish) instead of splitting the remaining levels a level at a time; -1: the
// device's default (8192 on CPUs, 32 on GPUs), 0: every level a level at a time. The tree is the
// same either way.
DeviceKdTree buildKdTree(Device& device, const cl::Buffer& photons, size_t n, KdTreeTiming* timing = nullptr,
                         int finishSize = -1);

// The memory plan's view of a build (buildKdTree's own loop, replayed): the finishSize -1
// stands for on a device of this type, and the entries of the chunk-count buffer a tree of n
// photons needs (0: none, every level finished by kdtree_finish).
int kdTreeFinishSize(cl_device_type type);
size_t kdTreeCountEntries(size_t n, int finishSize, cl_device_type type);

}  // namespace pcl
