// The work-group size of every launch that fixes one. Fixed, not tuned per device: PoCL compiles
// a kernel once per work-group size, and the kernels' local-memory tables are sized for it.
#pragma once
#include <cstddef>

#include "device/device.h"

namespace pcl {

constexpr size_t kWorkGroupSize = 64;

// n work-items rounded up to whole work-groups (the kernels skip ids ≥ n).
inline cl::NDRange wholeWorkGroups(size_t n) {
    return cl::NDRange((n + kWorkGroupSize - 1) / kWorkGroupSize * kWorkGroupSize);
}
inline cl::NDRange workGroup() { return cl::NDRange(kWorkGroupSize); }

}  // namespace pcl
