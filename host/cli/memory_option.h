// --max-buffer-mib N: a per-buffer cap on the OpenCL device, so a run on a big
// device behaves as it would on one whose CL_DEVICE_MAX_MEM_ALLOC_SIZE is N MiB: work splits into
// more batches (same results), and a buffer that cannot split fails before work with a message
// naming it (pipeline/memory_plan.h). Shared by photons, check, render and analyze.
#pragma once
#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

#include "device/device.h"

namespace pcl::cli {

// 0 (the default) is no cap; a given value must be a whole number of MiB, 1 .. 2^30.
inline CLI::Option* addMaxBufferMibOption(CLI::App* sub, uint64_t& mib, const std::string& help) {
    CLI::Validator wholeMiB(
        [](std::string& value) -> std::string {
            size_t used = 0;
            unsigned long long v = 0;
            try {
                v = std::stoull(value, &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (used != value.size() || value.empty() || value[0] == '-' || v < 1 || v > (1ull << 30))
                return "expected a whole number of MiB from 1 to 1073741824 (the largest buffer the device may "
                       "allocate), got '" +
                       value + "'";
            return {};
        },
        "MIB");
    return sub->add_option("--max-buffer-mib", mib, help)->check(wholeMiB);
}

// Caps every buffer of `device` at mib MiB; 0 leaves the driver's limit.
inline void applyBufferCap(Device& device, uint64_t mib) {
    if (mib) device.setBufferCap(size_t(mib) << 20);
}

}  // namespace pcl::cli
