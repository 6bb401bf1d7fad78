// CPU twin of deposit (kernels/README.md, "deposit"): an exclusive prefix sum of the per-path
// deposit counts gives each path its offset; slot k of path i goes to base + offset[i] + k.
// The map's order is (photon index, hit order), never the order of threads.
#pragma once
#include <cstdint>
#include <vector>

#include "shared/types.h"

namespace pcl {

// offsets[i] = counts[0] + … + counts[i-1]; offsets has counts.size() + 1 entries, the last
// the batch total.
std::vector<uint64_t> referenceExclusiveScan(const std::vector<uint32_t>& counts);

// Appends the batch's photons to `map` (base = map.size()).
void depositPhotonsReference(const std::vector<uint32_t>& counts, const std::vector<PclPhoton>& slots,
                             uint32_t slotsPerPath, std::vector<PclPhoton>& map);

}  // namespace pcl
