/* deposit.cl: a batch's photon records compacted into a map in a fixed order (kernels/README.md,
 * "deposit"): path order, then hit order, whatever order the work-items ran in.
 *
 * deposit_scan      in:  values[n]                   out: sums[g] per work-group of
 *                   PCL_SCAN_GROUP items, exclusive[i] = Σ values[k] over k < i in i's group
 * deposit_scan_add  in:  groupOffsets[g] (the scanned group sums)
 *                   out: exclusive[i] += groupOffsets[i / PCL_SCAN_GROUP]
 *   Together (the host recurses over the group sums) an exclusive prefix sum of the per-path
 *   counts: integer sums, so the result is exact and independent of scheduling.
 * deposit_scatter   in:  counts[n], offsets[n] (exclusive prefix sum), slots[S*n] slot-major
 *                   (record k of path i at k*n + i, as trace_photons writes them), base
 *                   out: map[base + offsets[i] + k] = slots[k*n + i] for k < counts[i]
 *   The host has grown the map to hold base + Σ counts before this runs. */
#include "shared/types.h"

#define PCL_SCAN_GROUP 256

/* Hillis & Steele (1986) inclusive scan in local memory: log2(256) = 8 steps, double buffered. */
__kernel __attribute__((reqd_work_group_size(PCL_SCAN_GROUP, 1, 1)))
void deposit_scan(__global const uint* values, __global uint* exclusive, __global uint* sums, uint n) {
    __local uint buf[2][PCL_SCAN_GROUP];
    const uint i = (uint)get_global_id(0);
    const uint l = (uint)get_local_id(0);
    const uint v = i < n ? values[i] : 0u;
    int src = 0;
    buf[0][l] = v;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint step = 1u; step < PCL_SCAN_GROUP; step <<= 1) {
        const uint x = buf[src][l] + (l >= step ? buf[src][l - step] : 0u);
        buf[1 - src][l] = x;
        src = 1 - src;
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    const uint inclusive = buf[src][l];
    if (i < n) exclusive[i] = inclusive - v;
    if (l == PCL_SCAN_GROUP - 1u) sums[get_group_id(0)] = inclusive;
}

__kernel void deposit_scan_add(__global uint* exclusive, __global const uint* groupOffsets, uint n) {
    const uint i = (uint)get_global_id(0);
    if (i < n) exclusive[i] += groupOffsets[i / PCL_SCAN_GROUP];
}

__kernel void deposit_scatter(__global const uint* counts, __global const uint* offsets,
                              __global const PclPhoton* slots, uint n,
                              __global PclPhoton* map, uint base) {
    const uint i = (uint)get_global_id(0);
    if (i >= n) return;
    const uint c = counts[i];
    __global const PclPhoton* src = slots + i;
    __global PclPhoton* dst = map + (size_t)base + offsets[i];
    for (uint k = 0u; k < c; ++k) dst[k] = src[(size_t)k * n];
}
