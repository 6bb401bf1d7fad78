#include "reference/hashgrid.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace pcl {

PclGridParams referenceGridParams(const std::vector<PclPhoton>& photons, float maxRadius) {
    if (!(maxRadius > 0.0f) || !std::isfinite(maxRadius)) throw std::invalid_argument("referenceGridParams: radius");
    PclGridParams g{};
    if (!photons.empty()) {
        g.ox = g.oy = g.oz = INFINITY;
        for (const PclPhoton& p : photons) {
            if (p.x < g.ox) g.ox = p.x;
            if (p.y < g.oy) g.oy = p.y;
            if (p.z < g.oz) g.oz = p.z;
        }
    }
    g.cellSize = maxRadius * 2.0f;
    g.invCellSize = 1.0f / g.cellSize;
    uint64_t size = 1;
    while (size < photons.size()) size *= 2;
    g.tableSize = uint32_t(size);
    g.photonCount = uint32_t(photons.size());
    return g;
}

int32_t referenceGridCoord(float p, float origin, float invCellSize) {
    const float d = p - origin;  // two separate float roundings, as the spec's formula reads
    float c = std::floor(d * invCellSize);
    c = std::max(-1.0e9f, std::min(1.0e9f, c));
    return int32_t(c);
}

uint32_t referenceGridHashOfCell(int32_t ix, int32_t iy, int32_t iz, uint32_t tableSize) {
    const uint32_t h = (uint32_t(ix) * 73856093u) ^ (uint32_t(iy) * 19349663u) ^ (uint32_t(iz) * 83492791u);
    return h % tableSize;
}

uint32_t referenceGridHash(const PclGridParams& g, float x, float y, float z) {
    return referenceGridHashOfCell(referenceGridCoord(x, g.ox, g.invCellSize),
                                   referenceGridCoord(y, g.oy, g.invCellSize),
                                   referenceGridCoord(z, g.oz, g.invCellSize), g.tableSize);
}

ReferenceHashGrid referenceHashGrid(const std::vector<PclPhoton>& photons, float maxRadius) {
    ReferenceHashGrid r;
    r.params = referenceGridParams(photons, maxRadius);
    const size_t n = photons.size();
    std::vector<uint32_t> hash(n);
    for (size_t i = 0; i < n; ++i) hash[i] = referenceGridHash(r.params, photons[i].x, photons[i].y, photons[i].z);
    r.order.resize(n);
    std::iota(r.order.begin(), r.order.end(), 0u);
    // (hash, index) as one 64-bit key: a plain sort gives the order without relying on stability.
    std::sort(r.order.begin(), r.order.end(),
              [&](uint32_t a, uint32_t b) { return (uint64_t(hash[a]) << 32 | a) < (uint64_t(hash[b]) << 32 | b); });
    r.keys.resize(n);
    for (size_t i = 0; i < n; ++i) r.keys[i] = hash[r.order[i]];
    r.cellStart.assign(r.params.tableSize, 0u);
    r.cellEnd.assign(r.params.tableSize, 0u);
    for (size_t i = 0; i < n;) {
        size_t j = i;
        while (j < n && r.keys[j] == r.keys[i]) ++j;
        r.cellStart[r.keys[i]] = uint32_t(i);
        r.cellEnd[r.keys[i]] = uint32_t(j);
        i = j;
    }
    return r;
}

}  // namespace pcl
