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

/* hashgrid_keys without the values (the bucketed build below carries the index in its points). */
__kernel void hashgrid_hashes(const PclGridParams params, __global const PclPhoton* photons, __global uint* keys) {
    const uint i = (uint)get_global_id(0);
    if (i >= params.photonCount) return;
    const PclPhoton p = photons[i];
    keys[i] = hash_grid_hash(hash_grid_coord(p.x, params.ox, params.invCellSize), hash_grid_coord(p.y, params.oy, params.invCellSize),
                        hash_grid_coord(p.z, params.oz, params.invCellSize), params.tableSize);
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

/* ---- The bucketed build (CPUs; pipeline/hashgrid.cpp, HashGridBuild::Bucketed) --------------
 * The same sorted order and tables as the radix sort and hashgrid_cells, without the sort's
 * passes and without hashgrid_cells' gather of every photon by its sorted index (a random read
 * over the whole photon array): a counting sort on the hash that moves the points with their
 * keys. The hash's top bits (its bucket) first: hashgrid_bucket_count counts them per chunk of
 * photons, hashgrid_bucket_scan turns the counts into positions, hashgrid_bucket_scatter moves
 * (key, point) pairs into their buckets (chunk after chunk, each in photon order: stable); then
 * hashgrid_bucket_cells sorts each bucket alone by the low bits, in cache: a bucket owns the
 * table entries [b << lowBits, (b + 1) << lowBits), so it counts its hashes in cellEnd, turns
 * the counts into the cell ranges and moves its pairs to their final places. Every position is a
 * function of the input alone (integer counts, no atomics). One work-item per chunk or bucket: a
 * GPU can run these kernels, but keeps the radix-sort build, whose work-groups suit it.
 *
 * hashgrid_bucket_count    in:  keys[n] (hashgrid_hashes: photon i's hash at i)
 *                          out: counts[b * chunks + c] = photons of chunk c in bucket b
 * hashgrid_bucket_scan     counts, exclusively scanned in place in that bucket-major order
 * hashgrid_bucket_scatter  in:  keys, photons, counts (scanned)
 *                          out: bucketKeys[n], bucketPoints[n] in bucket order; counts[b * chunks + c]
 *                          advanced past chunk c's photons of bucket b, so counts[b * chunks +
 *                          chunks - 1] is the end of bucket b (and the start of bucket b + 1)
 * hashgrid_bucket_cells    in:  bucketKeys, bucketPoints, counts (as the scatter left them)
 *                          out: cellStart, cellEnd (every entry: an empty hash 0, 0), keys,
 *                          values, points in sorted order */
__kernel __attribute__((reqd_work_group_size(1, 1, 1)))
void hashgrid_bucket_count(__global const uint* keys, uint n, uint chunkSize, uint lowBits, uint buckets,
                           __global uint* counts) {
    const uint c = (uint)get_group_id(0), chunks = (uint)get_num_groups(0);
    for (uint b = 0u; b < buckets; ++b) counts[b * chunks + c] = 0u;
    const uint end = min(n, (c + 1u) * chunkSize);
    for (uint i = c * chunkSize; i < end; ++i) counts[(keys[i] >> lowBits) * chunks + c] += 1u;
}

__kernel __attribute__((reqd_work_group_size(1, 1, 1)))
void hashgrid_bucket_scan(__global uint* counts, uint entries) {
    uint run = 0u;
    for (uint e = 0u; e < entries; ++e) {
        const uint c = counts[e];
        counts[e] = run;
        run += c;
    }
}

__kernel __attribute__((reqd_work_group_size(1, 1, 1)))
void hashgrid_bucket_scatter(__global const uint* keys, __global const PclPhoton* photons, uint n, uint chunkSize,
                             uint lowBits, __global uint* counts, __global uint* bucketKeys,
                             __global float4* bucketPoints) {
    const uint c = (uint)get_group_id(0), chunks = (uint)get_num_groups(0);
    const uint end = min(n, (c + 1u) * chunkSize);
    for (uint i = c * chunkSize; i < end; ++i) {
        const uint key = keys[i];
        const uint at = counts[(key >> lowBits) * chunks + c]++;
        const PclPhoton p = photons[i];
        bucketKeys[at] = key;
        bucketPoints[at] = (float4)(p.x, p.y, p.z, as_float(i));
    }
}

__kernel __attribute__((reqd_work_group_size(1, 1, 1)))
void hashgrid_bucket_cells(__global const uint* bucketKeys, __global const float4* bucketPoints, uint chunks,
                           uint lowBits, __global const uint* counts, __global uint* cellStart,
                           __global uint* cellEnd, __global uint* keys, __global uint* values,
                           __global float4* points) {
    const uint b = (uint)get_group_id(0);
    const uint begin = b == 0u ? 0u : counts[b * chunks - 1u];
    const uint end = counts[(b + 1u) * chunks - 1u];
    const uint h0 = b << lowBits, h1 = (b + 1u) << lowBits;
    for (uint h = h0; h < h1; ++h) cellEnd[h] = 0u;
    for (uint j = begin; j < end; ++j) cellEnd[bucketKeys[j]] += 1u;
    uint run = begin;
    for (uint h = h0; h < h1; ++h) {  /* cellEnd becomes each cell's cursor, its end once moved */
        const uint count = cellEnd[h];
        cellStart[h] = count ? run : 0u;
        cellEnd[h] = count ? run : 0u;
        run += count;
    }
    for (uint j = begin; j < end; ++j) {
        const uint key = bucketKeys[j];
        const uint at = cellEnd[key]++;
        const float4 p = bucketPoints[j];
        keys[at] = key;
        values[at] = as_uint(p.w);
        points[at] = p;
    }
}
