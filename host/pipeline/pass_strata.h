// The cells of a pass's stratification patterns (kernels/shared/stratify.h), made once on the
// host for the kernels that shift them per pixel (final_gather_trace, direct_light). Pattern w
// of a pass is word w of the Philox block (PCL_PASS_PATTERN_PATH, bounce, 0) of its stream; entry
// 2(w·count + s) and the next hold sample s's cell (stratify_cmj_cell). The twins permute each
// sample themselves, so the table is checked with every stage cross-check.
#pragma once
#include <cstdint>
#include <vector>

namespace pcl {

std::vector<uint32_t> passStrata(uint64_t seed, uint32_t stream, uint32_t bounce, uint32_t patterns, uint32_t count);

}  // namespace pcl
