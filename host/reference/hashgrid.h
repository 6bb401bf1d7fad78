// CPU twin of the hash grid (kernels/README.md, "Photon maps", hash grid), written from the
// spec: cell = ⌊(p − origin) · invCellSize⌋ per axis in float (clamped to ±1e9 before the
// integer conversion), hash = (ix·73856093 ^ iy·19349663 ^ iz·83492791) mod tableSize in
// unsigned 32-bit arithmetic, photons ordered by (hash, photon index), cellStart/cellEnd per hash.
#pragma once
#include <cstdint>
#include <vector>

#include "shared/types.h"

namespace pcl {

struct ReferenceHashGrid {
    PclGridParams params{};
    std::vector<uint32_t> keys;                // hash of each photon, in sorted order
    std::vector<uint32_t> order;               // photon indices sorted by (hash, index)
    std::vector<uint32_t> cellStart, cellEnd;  // per hash: [start, end) into order; 0, 0 if empty
};

// Grid parameters for a search radius r: origin = bounds minimum of the photons (0 if none),
// cellSize = 2r, invCellSize = 1/cellSize, tableSize = smallest power of two ≥ max(n, 1).
PclGridParams referenceGridParams(const std::vector<PclPhoton>& photons, float maxRadius);

// The hash of the cell holding (x, y, z).
uint32_t referenceGridHash(const PclGridParams& params, float x, float y, float z);
// One cell coordinate of a position along an axis with origin o.
int32_t referenceGridCoord(float p, float origin, float invCellSize);
uint32_t referenceGridHashOfCell(int32_t ix, int32_t iy, int32_t iz, uint32_t tableSize);

ReferenceHashGrid referenceHashGrid(const std::vector<PclPhoton>& photons, float maxRadius);

}  // namespace pcl
