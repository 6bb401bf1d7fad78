// Stage 3 of the photon pass: a batch's deposited records appended to a photon map in path
// order, then hit order, through an exclusive prefix sum of the per-path counts
// (kernels/deposit.cl, spec in kernels/README.md "deposit"). The twin is
// host/reference/deposit.cpp.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "shared/types.h"

namespace pcl {

// A photon map on the device: `count` records in a buffer of `capacity`. Grown (copied into a
// larger buffer) before a scatter that would overflow it; `growths` counts those events.
struct DevicePhotonMap {
    cl::Buffer photons;
    size_t count = 0;
    size_t capacity = 0;
    uint32_t growths = 0;
    std::string name = "photon map";  // in allocation labels and errors ("photon pass: global map")
};

DevicePhotonMap makeDevicePhotonMap(Device& device, size_t capacity, const std::string& name = "photon map");

// Records one buffer of maxAlloc bytes holds: the largest map a device (or a --max-buffer-mib
// cap) allows. Growth stops there; a map that needs more fails with an InputError saying so.
inline size_t maxMapRecords(size_t maxAlloc) { return maxAlloc / sizeof(PclPhoton); }

// Device seconds of one deposit, from event profiling.
struct DepositTiming {
    double scanSeconds = 0.0, growSeconds = 0.0, scatterSeconds = 0.0;
};

// Exclusive prefix sum of n values into `exclusive` (device buffers, n >= 1); returns the total
// (a small blocking read). Work-groups of 256 scanned by deposit_scan, their sums scanned
// recursively and added back by deposit_scan_add.
uint64_t exclusiveScan(Device& device, const cl::Buffer& values, cl::Buffer& exclusive, size_t n,
                       double* seconds = nullptr);

// Appends the records of `paths` paths (counts[i] valid records, record k of path i in
// slots[k*paths + i]: the device's slot-major layout) to map: scan, grow the map if base + total
// exceeds its capacity, scatter. Returns the records added.
size_t depositPhotons(Device& device, const cl::Buffer& counts, const cl::Buffer& slots, uint32_t paths,
                      DevicePhotonMap& map, DepositTiming* timing = nullptr);

// The device's slot-major slots of `paths` paths (record k of path i at k*paths + i) from the
// twin's path-major ones (at i*S + k), and back: for checks and tests that move slots between
// the two.
std::vector<PclPhoton> slotMajor(const std::vector<PclPhoton>& pathMajor, size_t paths, uint32_t slotsPerPath);
std::vector<PclPhoton> pathMajor(const std::vector<PclPhoton>& slotMajor, size_t paths, uint32_t slotsPerPath);

}  // namespace pcl
