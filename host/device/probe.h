// Probe: asks the device compiler what it made of the shared headers (kernels/probe.cl), so
// tests can check that host and device agree on struct layouts and on the RNG.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "device/device.h"

namespace pcl {

struct SharedStruct {
    const char* name;  // e.g. "PclRay"
    size_t hostSize;   // sizeof on the host
};

// Every buffer struct of kernels/shared/types.h, in PCL_SHARED_STRUCTS order.
const std::vector<SharedStruct>& sharedStructs();

// sizeof of each sharedStructs() entry as the device compiler sees it, same order.
std::vector<uint32_t> probeDeviceSizes(Device& device);

// Philox4x32-10 evaluated on the device, one (ctr, key) pair per work-item.
struct PhiloxInput {
    std::array<uint32_t, 4> ctr;
    std::array<uint32_t, 2> key;
};
std::vector<std::array<uint32_t, 4>> probeDevicePhilox(Device& device, const std::vector<PhiloxInput>& in);

// rng_next_u32 for dimensions 0..count-1 of (seed, path, bounce, stream), on the device.
std::vector<uint32_t> probeDeviceRngStream(Device& device, uint64_t seed, uint32_t path, uint32_t bounce,
                                           uint32_t stream, size_t count);

}  // namespace pcl
