// The hash grid over a photon map (kernels/hashgrid.cl; kernels/README.md, "Photon maps"), the
// alternative to the kd-tree for k-nearest-neighbour search: cells of size 2 r_max, so a query
// of radius ≤ r_max reads at most 2×2×2 cells; cells hashed into a power-of-two table; photons
// ordered by (hash, photon index); per hash the [start, end) of its photons in that order. The
// twin is host/reference/hashgrid.cpp.
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
    size_t count = 0;               // photons
    cl::Buffer keys, order;         // sorted hashes and the photon indices in that order
    cl::Buffer cellStart, cellEnd;  // tableSize entries each
    cl::Buffer points;              // count float4
    // Device time by step: the hashes; their sort (Sorted) or the count and move into buckets
    // (Bucketed); the cell ranges and points (hashgrid_cells or hashgrid_bucket_cells).
    double keySeconds = 0, sortSeconds = 0, rangeSeconds = 0;
};

// How the (hash, photon index) order is made; both give the same grid, bit for bit
// (kernels/hashgrid.cl). Sorted: the device radix sort of (hash, index), then each photon
// gathered by its sorted index (work-groups suit GPUs). Bucketed: a counting sort that moves the
// points with their hashes, into buckets by the top hash bits, then each bucket by the low bits
// in cache, one work-item per chunk or bucket (CPUs: no random read of the photons).
// ForDevice: Bucketed on a CPU, Sorted elsewhere.
enum class HashGridBuild { ForDevice, Sorted, Bucketed };

// Builds the grid of `count` photons already on the device (params.photonCount must be count).
DeviceHashGrid buildHashGrid(Device& device, const cl::Buffer& photons, size_t count, const PclGridParams& params,
                             HashGridBuild build = HashGridBuild::ForDevice);

// The bucketed build's shape for n photons on a device with `computeUnits` cores: photons per
// chunk and chunks (the count and scatter kernels' work-items), the low hash bits sorted within
// a bucket and the buckets (the cells kernel's work-items). For the memory plan and tests.
struct HashGridBucketShape {
    size_t chunkSize = 0, chunks = 0;
    int lowBits = 0;
    size_t buckets = 0;
};
HashGridBucketShape hashGridBucketShape(size_t n, uint32_t tableSize, size_t computeUnits);

// The build a device of this type gets for ForDevice.
HashGridBuild hashGridBuildFor(cl_device_type type);

}  // namespace pcl
