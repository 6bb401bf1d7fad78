/* sort.cl: stable LSD radix sort of (key, value) pairs, PCL_SORT_RADIX_BITS bits per pass at
 * most (kernels/README.md, "Photon maps", sort). Keys are uint, or ulong with -DPCL_SORT_KEY64=1;
 * values are uint.
 *
 * One pass over digit d = (key >> shift) & mask (the host spreads the caller's sortBits evenly
 * over the fewest passes) is three launches:
 *   sort_histogram  per tile of PCL_SORT_TILE keys: hist[d * tiles + t] = keys of digit d in tile t
 *   sort_scan       one work-group: offsets = exclusive prefix sum of hist (digit-major, so
 *                   offsets[d * tiles + t] is where tile t's first key of digit d goes)
 *   sort_scatter    per tile: every key goes to offsets[d * tiles + t] + (keys of digit d before
 *                   it in the tile)
 * Work-item l of a tile owns the PCL_SORT_ITEMS consecutive keys l*ITEMS .. l*ITEMS+ITEMS-1, so
 * "keys of digit d before it in the tile" = Σ counts[d][l' < l] + the keys of digit d this
 * work-item has already placed: a scan of the per-work-item digit counts — none when a tile is
 * one work-item (PCL_SORT_GROUP == 1, the CPU shape). Every position is a function of the input
 * alone (integer counts, no atomics), so the sort is stable and deterministic by construction,
 * on any device and with any scheduling.
 *
 * Bucketed (-DPCL_SORT_BUCKETED=1, the CPU shape from 2^18 pairs): one such pass on the top
 * digit, then sort_buckets sorts each top-digit bucket alone by the low bits (below). */
#include "shared/types.h"

#ifndef PCL_SORT_KEY64
#define PCL_SORT_KEY64 0
#endif
#if PCL_SORT_KEY64
typedef ulong sort_key;
#else
typedef uint sort_key;
#endif

/* The host passes all three (pipeline/sort.cpp); these are its values. */
#ifndef PCL_SORT_RADIX_BITS
#define PCL_SORT_RADIX_BITS 8
#endif
#ifndef PCL_SORT_GROUP
#define PCL_SORT_GROUP 16
#endif
#ifndef PCL_SORT_ITEMS
#define PCL_SORT_ITEMS 512
#endif
#define PCL_SORT_TILE (PCL_SORT_GROUP * PCL_SORT_ITEMS)
#define PCL_SORT_RADIX (1u << PCL_SORT_RADIX_BITS)

/* counts[d * GROUP + l]: keys of digit d among work-item l's items. */
static inline void sort_count_items(__global const sort_key* keys, uint n, uint shift, uint mask,
                                    __local uint* counts, uint l, uint tile) {
    for (uint d = 0u; d < PCL_SORT_RADIX; ++d) counts[d * PCL_SORT_GROUP + l] = 0u;
    const uint begin = tile * (uint)PCL_SORT_TILE + l * (uint)PCL_SORT_ITEMS;
    const uint end = min(begin + (uint)PCL_SORT_ITEMS, n);
    for (uint i = begin; i < end; ++i) counts[(uint)((keys[i] >> shift) & mask) * PCL_SORT_GROUP + l] += 1u;
}

__kernel __attribute__((reqd_work_group_size(PCL_SORT_GROUP, 1, 1)))
void sort_histogram(__global const sort_key* keys, uint n, uint shift, uint mask, __global uint* hist) {
    __local uint counts[PCL_SORT_RADIX * PCL_SORT_GROUP];
    const uint l = (uint)get_local_id(0);
    const uint t = (uint)get_group_id(0);
    const uint tiles = (uint)get_num_groups(0);
    sort_count_items(keys, n, shift, mask, counts, l, t);
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint d = l; d < PCL_SORT_RADIX; d += PCL_SORT_GROUP) {
        uint s = 0u;
        for (uint k = 0u; k < PCL_SORT_GROUP; ++k) s += counts[d * PCL_SORT_GROUP + k];
        hist[d * tiles + t] = s;
    }
}

/* The exclusive prefix sum over the work-group of each work-item's s: a Hillis & Steele scan,
 * double-buffered in buf. Every work-item of the group calls it (barriers inside). */
inline uint sort_group_exclusive_scan(uint s, __local uint buf[2][PCL_SORT_GROUP], uint l) {
    int src = 0;
    buf[0][l] = s;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint step = 1u; step < PCL_SORT_GROUP; step <<= 1) {
        const uint x = buf[src][l] + (l >= step ? buf[src][l - step] : 0u);
        buf[1 - src][l] = x;
        src = 1 - src;
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    return buf[src][l] - s;
}

/* Exclusive prefix sum of m values in place, by one work-group: work-item l sums a contiguous
 * chunk, a Hillis & Steele scan of the chunk sums, then each chunk rewritten. */
__kernel __attribute__((reqd_work_group_size(PCL_SORT_GROUP, 1, 1)))
void sort_scan(__global uint* values, uint m) {
    __local uint buf[2][PCL_SORT_GROUP];
    const uint l = (uint)get_local_id(0);
    const uint chunk = (m + PCL_SORT_GROUP - 1u) / PCL_SORT_GROUP;
    const uint begin = min(l * chunk, m);
    const uint end = min(begin + chunk, m);
    uint s = 0u;
    for (uint i = begin; i < end; ++i) s += values[i];
    uint run = sort_group_exclusive_scan(s, buf, l);
    for (uint i = begin; i < end; ++i) {
        const uint v = values[i];
        values[i] = run;
        run += v;
    }
}

__kernel __attribute__((reqd_work_group_size(PCL_SORT_GROUP, 1, 1)))
void sort_scatter(__global const sort_key* keysIn, __global const uint* valuesIn, uint n, uint shift, uint mask,
                  __global const uint* offsets, __global sort_key* keysOut, __global uint* valuesOut) {
    const uint t = (uint)get_group_id(0);
    const uint tiles = (uint)get_num_groups(0);
#if PCL_SORT_GROUP == 1
    /* One work-item per tile: its keys of digit d go to offsets[d * tiles + t] onwards, in order;
     * no recount. */
    __local uint base[PCL_SORT_RADIX];
    for (uint d = 0u; d < PCL_SORT_RADIX; ++d) base[d] = offsets[d * tiles + t];
    const uint begin = t * (uint)PCL_SORT_TILE;
    const uint end = min(begin + (uint)PCL_SORT_TILE, n);
    for (uint i = begin; i < end; ++i) {
        const sort_key k = keysIn[i];
        const uint d = (uint)((k >> shift) & mask);
        const uint dst = base[d];
        base[d] = dst + 1u;
        keysOut[dst] = k;
        valuesOut[dst] = valuesIn[i];
    }
#else
    __local uint counts[PCL_SORT_RADIX * PCL_SORT_GROUP];
    __local uint buf[2][PCL_SORT_GROUP];
    __local uint base[PCL_SORT_RADIX];
    const uint l = (uint)get_local_id(0);
    sort_count_items(keysIn, n, shift, mask, counts, l, t);
    barrier(CLK_LOCAL_MEM_FENCE);

    /* Exclusive scan of counts in its digit-major order: work-item l scans entries
     * l*RADIX .. l*RADIX+RADIX-1 (GROUP * RADIX entries in all). */
    uint s = 0u;
    for (uint j = 0u; j < PCL_SORT_RADIX; ++j) s += counts[l * PCL_SORT_RADIX + j];
    uint run = sort_group_exclusive_scan(s, buf, l);
    for (uint j = 0u; j < PCL_SORT_RADIX; ++j) {
        const uint v = counts[l * PCL_SORT_RADIX + j];
        counts[l * PCL_SORT_RADIX + j] = run;
        run += v;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    /* counts[d*GROUP + l] is now the tile-local rank of work-item l's first key of digit d,
     * counting every smaller digit of the tile; base[d] turns it into a global position. */
    for (uint d = l; d < PCL_SORT_RADIX; d += PCL_SORT_GROUP) base[d] = offsets[d * tiles + t] - counts[d * PCL_SORT_GROUP];
    barrier(CLK_LOCAL_MEM_FENCE);

    const uint begin = t * (uint)PCL_SORT_TILE + l * (uint)PCL_SORT_ITEMS;
    const uint end = min(begin + (uint)PCL_SORT_ITEMS, n);
    for (uint i = begin; i < end; ++i) {
        const sort_key k = keysIn[i];
        const uint d = (uint)((k >> shift) & mask);
        const uint dst = base[d] + counts[d * PCL_SORT_GROUP + l];
        counts[d * PCL_SORT_GROUP + l] += 1u;
        keysOut[dst] = k;
        valuesOut[dst] = valuesIn[i];
    }
#endif
}

#if PCL_SORT_BUCKETED

/* The rest of a bucketed sort (pipeline/sort.cpp): after one pass on the top digit (keys and
 * values in keysB/valuesB, grouped by that digit, stable), work-item b sorts bucket b — the
 * pairs of top digit b, offsets[b * tiles] .. offsets[(b + 1) * tiles] (or n) — by the low
 * lowBits bits, alone, in lowPasses stable LSD passes (digits split evenly over the passes, the
 * first ones one bit wider), ping-ponging within the bucket's range between the B and A buffers;
 * a bucket is small enough to stay in cache. One work-item sees the whole bucket, so a digit's
 * counts do not depend on the order: one read counts pass 0's digits, and each pass counts the
 * next pass's digits while it moves the pairs. A pass whose digit is the same for the whole
 * bucket is skipped (only counted); the bucket ends in A (copied there if the passes left it in
 * B). Positions are integer counts of the input alone: stable and deterministic. */
/* Bits of pass p when `bits` are split over `passes` passes, the first ones one bit wider
 * (pipeline/sort.cpp splits the whole key the same way). */
inline uint sort_digit_bits(uint bits, uint passes, uint p) {
    return bits / passes + (p < bits % passes ? 1u : 0u);
}

__kernel __attribute__((reqd_work_group_size(1, 1, 1)))
void sort_buckets(__global sort_key* keysA, __global uint* valuesA, __global sort_key* keysB, __global uint* valuesB,
                  __global const uint* offsets, uint tiles, uint n, uint lowBits, uint lowPasses) {
    __local uint counts[2 * PCL_SORT_RADIX];
    const uint b = (uint)get_group_id(0);
    const uint begin = offsets[b * tiles];
    const uint end = b + 1u < (uint)get_num_groups(0) ? offsets[(b + 1u) * tiles] : n;
    if (end - begin < 2u) {
        if (end > begin) {
            keysA[begin] = keysB[begin];
            valuesA[begin] = valuesB[begin];
        }
        return;
    }
    __local uint* cur = counts;
    __local uint* next = counts + PCL_SORT_RADIX;
    uint shift = 0u, bits = sort_digit_bits(lowBits, lowPasses, 0u);
    for (uint d = 0u; d < PCL_SORT_RADIX; ++d) cur[d] = 0u;
    for (uint i = begin; i < end; ++i) cur[(uint)(keysB[i] & ((1u << bits) - 1u))] += 1u;
    bool inB = true;
    for (uint p = 0u; p < lowPasses; ++p) {
        /* cur: the counts of pass p's digit; next gets pass p + 1's while pass p moves the pairs */
        const uint mask = (1u << bits) - 1u;
        const uint nextShift = shift + bits;
        const uint nextBits = p + 1u < lowPasses ? sort_digit_bits(lowBits, lowPasses, p + 1u) : 0u;
        const uint nextMask = (1u << nextBits) - 1u;
        bool same = false;
        uint run = begin;
        for (uint d = 0u; d < PCL_SORT_RADIX; ++d) {
            const uint c = cur[d];
            same = same || c == end - begin;
            cur[d] = run;
            run += c;
            next[d] = 0u;
        }
        __global const sort_key* ks = inB ? keysB : keysA;
        __global const uint* vs = inB ? valuesB : valuesA;
        __global sort_key* kd = inB ? keysA : keysB;
        __global uint* vd = inB ? valuesA : valuesB;
        if (same) { /* the pass would move nothing */
            if (nextBits)
                for (uint i = begin; i < end; ++i) next[(uint)((ks[i] >> nextShift) & nextMask)] += 1u;
        } else {
            for (uint i = begin; i < end; ++i) {
                const sort_key k = ks[i];
                const uint d = (uint)((k >> shift) & mask);
                const uint dst = cur[d];
                cur[d] = dst + 1u;
                kd[dst] = k;
                vd[dst] = vs[i];
                next[(uint)((k >> nextShift) & nextMask)] += 1u;
            }
            inB = !inB;
        }
        __local uint* t = cur;
        cur = next;
        next = t;
        shift = nextShift;
        bits = nextBits;
    }
    if (inB)
        for (uint i = begin; i < end; ++i) {
            keysA[i] = keysB[i];
            valuesA[i] = valuesB[i];
        }
}
#endif

/* Order-preserving float → uint key (kernels/README.md, sort): sign clear → b ^ 0x80000000,
 * sign set → ~b. values[i] = i, ready for an index-stable sort. */
__kernel void sort_float_keys(__global const float* x, uint n, __global uint* keys, __global uint* values) {
    const uint i = (uint)get_global_id(0);
    if (i >= n) return;
    const uint b = as_uint(x[i]);
    keys[i] = (b & 0x80000000u) ? ~b : (b ^ 0x80000000u);
    values[i] = i;
}
