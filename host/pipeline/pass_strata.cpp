#include "pipeline/pass_strata.h"

#include <algorithm>

#include "core/error.h"
#include "shared/rng.h"
#include "shared/stratify.h"
#include "shared/types.h"

namespace pcl {

std::vector<uint32_t> passStrata(uint64_t seed, uint32_t stream, uint32_t bounce, uint32_t patterns, uint32_t count) {
    if (patterns > 4)
        throw InternalError("pass strata: " + std::to_string(patterns) +
                            " patterns: expected at most 4 (one Philox block)");
    if (count >= (1u << 24))
        throw InternalError("pass strata: " + std::to_string(count) + " samples a pattern: expected below 2^24");
    uint32_t words[4];
    rng_block(seed, PCL_PASS_PATTERN_PATH, bounce, 0, stream, words);
    // A kernel binds the table even when it reads none of it (no light samples): never empty.
    std::vector<uint32_t> cells(std::max<size_t>(size_t(2) * patterns * count, 2), 0u);
    for (uint32_t w = 0; w < patterns; ++w)
        for (uint32_t s = 0; s < count; ++s) {
            const size_t e = 2 * (size_t(w) * count + s);
            stratify_cmj_cell(s, count, words[w], &cells[e], &cells[e + 1]);
        }
    return cells;
}

cl::Buffer uploadPassStrata(Device& device, uint32_t seedLo, uint32_t seedHi, uint32_t stream, uint32_t bounce,
                            uint32_t patterns, uint32_t count, const std::string& what) {
    const uint64_t seed = uint64_t(seedLo) | uint64_t(seedHi) << 32;
    return device.upload(passStrata(seed, stream, bounce, patterns, count), CL_MEM_READ_ONLY, what);
}

}  // namespace pcl
