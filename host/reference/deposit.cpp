#include "reference/deposit.h"

namespace pcl {

std::vector<uint64_t> referenceExclusiveScan(const std::vector<uint32_t>& counts) {
    std::vector<uint64_t> offsets(counts.size() + 1, 0);
    for (size_t i = 0; i < counts.size(); ++i) offsets[i + 1] = offsets[i] + counts[i];
    return offsets;
}

void depositPhotonsReference(const std::vector<uint32_t>& counts, const std::vector<PclPhoton>& slots,
                             uint32_t slotsPerPath, std::vector<PclPhoton>& map) {
    const std::vector<uint64_t> offsets = referenceExclusiveScan(counts);
    const size_t base = map.size();
    map.resize(base + offsets.back());  // grown before the scatter, never truncated
    for (size_t i = 0; i < counts.size(); ++i)
        for (uint32_t k = 0; k < counts[i]; ++k) map[base + offsets[i] + k] = slots[i * slotsPerPath + k];
}

}  // namespace pcl
