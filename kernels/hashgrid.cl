/* hashgrid.cl: the hashed uniform grid over a photon map (kernels/README.md, "Photon maps";
 * the HashGrid of SmallVCM): cell (ix, iy, iz) = ⌊(p − origin) · invCellSize⌋, hash =
 * (ix·73856093 ^ iy·19349663 ^ iz·83492791) mod tableSize in unsigned 32-bit arithmetic,
 * photons ordered by (hash, photon index), and per hash the range of that order holding it.
 *
 * hashgrid_keys    in:  params, photons[n]     out: keys[i] = hash of photon i's cell, values[i] = i
 *   The host then sorts the (key, value) pairs stably (device radix sort), so equal hashes keep
 *   photon index order and the result never depends on scheduling.
 * hashgrid_cells   in:  sorted keys[n] and values[n], photons
 *                  out: cellStart[h], cellEnd[h] for every hash h present ([start, end) into the
 *   sorted order; the host zero-fills both tables first, so an empty hash has start = end = 0),
 *   and points[i] = (x, y, z, photon index bits) of the i-th photon in sorted order: what
 *   knn_hashgrid reads, one 16-byte load per candidate.
 *
 * Cell coordinates are clamped to ±1e9 before the integer conversion (a tiny cell over a huge
 * map must not overflow int); clamping is monotonic, so a query's cell range still covers its
 * photons. No contraction: the host twin computes the same float products. */
#pragma OPENCL FP_CONTRACT OFF
#include "shared/types.h"
#include "shared/hash_grid.h"

__kernel void hashgrid_keys(const PclGridParams params, __global const PclPhoton* photons,
                            __global uint* keys, __global uint* values) {
    const uint i = (uint)get_global_id(0);
    if (i >= params.photonCount) return;
    const PclPhoton p = photons[i];
    keys[i] = hash_grid_hash(hash_grid_coord(p.x, params.ox, params.invCellSize), hash_grid_coord(p.y, params.oy, params.invCellSize),
                        hash_grid_coord(p.z, params.oz, params.invCellSize), params.tableSize);
    values[i] = i;
}

/* One pass over the sorted order: the ranges and the points together (one launch, keys and
 * values read once). */
__kernel void hashgrid_cells(__global const uint* keys, __global const uint* values, uint n,
                             __global const PclPhoton* photons, __global uint* cellStart, __global uint* cellEnd,
                             __global float4* points) {
    const uint i = (uint)get_global_id(0);
    if (i >= n) return;
    const uint key = keys[i];
    if (i == 0u || keys[i - 1u] != key) cellStart[key] = i;
    if (i + 1u == n || keys[i + 1u] != key) cellEnd[key] = i + 1u;
    const uint j = values[i];
    const PclPhoton p = photons[j];
    points[i] = (float4)(p.x, p.y, p.z, as_float(j));
}
