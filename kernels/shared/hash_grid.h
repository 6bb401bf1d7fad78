/* hash_grid.h: the hashed uniform grid's cell and hash (kernels/README.md, "Photon maps"; the
 * HashGrid of SmallVCM), one definition for the kernels that build it (hashgrid.cl) and read it
 * (knn.cl, volume_estimate.cl), so a photon's cell is found again exactly. Kernel-only: the CPU
 * twins derive the same formula from the README.
 *
 *   hash_grid_coord  ⌊(p − origin) · invCellSize⌋, clamped to ±1e9 before the integer conversion
 *                    (a tiny cell over a huge map must not overflow int; clamping is monotonic,
 *                    so a query's cell range still covers its photons)
 *   hash_grid_hash   (ix·73856093 ^ iy·19349663 ^ iz·83492791) mod tableSize, unsigned 32-bit,
 *                    tableSize a power of two */
#ifndef PCL_HASH_GRID_H
#define PCL_HASH_GRID_H

#define PCL_GRID_COORD_LIMIT 1.0e9f

/* Clamped first, then floored by a conversion instead of floor (PoCL's floor is a branchy
 * software routine): the truncation, less one where it rounded a
 * negative fraction up. The same integer: ±1e9 are integers, so clamping before or after the
 * floor agrees, and the comparison is exact (below 2^23 the truncation is a float, above it
 * every float is an integer). */
inline int hash_grid_coord(float p, float origin, float invCellSize) {
    const float c = clamp((p - origin) * invCellSize, -PCL_GRID_COORD_LIMIT, PCL_GRID_COORD_LIMIT);
    const int t = (int)c;
    return (float)t > c ? t - 1 : t;
}

inline uint hash_grid_hash(int ix, int iy, int iz, uint tableSize) {
    const uint h = ((uint)ix * 73856093u) ^ ((uint)iy * 19349663u) ^ ((uint)iz * 83492791u);
    return h & (tableSize - 1u); /* tableSize is a power of two: the same as mod */
}

#endif /* PCL_HASH_GRID_H */
