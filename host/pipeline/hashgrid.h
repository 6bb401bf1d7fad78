// The hash grid over a photon map (kernels/hashgrid.cl; kernels/README.md, "Photon maps"), the
// alternative to the kd-tree for k-nearest-neighbour search: cells of size 2 r_max, so a query
// of radius ≤ r_max reads at most 2×2×2 cells; cells hashed into a power-of-two table; photons
// ordered by (hash, photon index) with the device radix sort; per hash the [start, end) of its
// photons in that order. The twin is host/reference/hashgrid.cpp.
#pragma once
#include <cstdint>
#include <vector>

#include "device/device.h"
#include "shared/types.h"

namespace pcl {

// origin = the map's bounds minimum (0 for an empty map), cellSize = 2 maxRadius,
// invCellSize = 1 / cellSize, tableSize = the smallest power of two ≥ max(photons, 1).
// maxRadius must be positive and finite (InternalError otherwise).
PclGridParams hashGridParams(const std::vector<PclPhoton>& photons, float maxRadius);

// A hash grid on the device. `points` holds the photons in sorted order as float4
// (x, y, z, photon index as the bits of w): knn_hashgrid reads only it and the two tables.
struct DeviceHashGrid {
    PclGridParams params{};
    size_t count = 0;                                          // photons
    cl::Buffer keys, order;                                    // sorted hashes and the photon indices in that order
    cl::Buffer cellStart, cellEnd;                             // tableSize entries each
    cl::Buffer points;                                         // count float4
    double keySeconds = 0, sortSeconds = 0, rangeSeconds = 0;  // device time by step
};

// Builds the grid of `count` photons already on the device (params.photonCount must be count).
DeviceHashGrid buildHashGrid(Device& device, const cl::Buffer& photons, size_t count, const PclGridParams& params);

}  // namespace pcl
