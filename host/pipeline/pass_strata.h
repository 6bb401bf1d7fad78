// The cells of a pass's stratification patterns (kernels/shared/stratify.h), made once on the
// host for the kernels that shift them per pixel (final_gather_trace, direct_light). Pattern w
// of a pass is word w of the Philox block (PCL_PASS_PATTERN_PATH, bounce, 0) of its stream; entry
// 2(w·count + s) and the next hold sample s's cell (stratify_cmj_cell). The twins permute each
// sample themselves, so the table is checked with every stage cross-check.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"

namespace pcl {

std::vector<uint32_t> passStrata(uint64_t seed, uint32_t stream, uint32_t bounce, uint32_t patterns, uint32_t count);

// The same table on the device (read-only), for the pass whose seed is (seedLo, seedHi).
cl::Buffer uploadPassStrata(Device& device, uint32_t seedLo, uint32_t seedHi, uint32_t stream, uint32_t bounce,
                            uint32_t patterns, uint32_t count, const std::string& what);

}  // namespace pcl
