/* kdtree.cl: Jensen's left-balanced kd-tree built on the device level by level by sorting
 * (kernels/README.md, "Photon maps", kd-tree; Jensen 2001 §6.3). The tree is a heap over the
 * photon array: node h has children 2h+1 and 2h+2, split axis in bits 27..28 of `packed`.
 *
 * State between levels: sub[i] = the heap node whose subtree photon i is in (PCL_KD_DONE once
 * the photon is a node). One level L (nodes levelFirst = 2^L − 1 .. levelFirst + 2^L − 1):
 *   kdtree_keys     photon order i: key = (sub[i] − levelFirst) << rankBits | rank of photon i
 *                   on the subtree's split axis (kdtree_rank_*: its place in the map ordered by
 *                   (flipped coordinate key, photon index)), or levelCount << rankBits for
 *                   placed photons; value = i. (The README's subtree << 32 | coordinate key,
 *                   stable, orders the same way; the ranks need fewer bits and passes.)
 *   (radix sort)    each subtree's photons end up contiguous, ordered by (coordinate key,
 *                   photon index)
 *   kdtree_segments first and one-past-last sorted position of each subtree
 *   kdtree_assign   position r in its subtree of n photons: r = left(n) → the photon is node h;
 *                   r < left → sub = 2h+1, r > left → sub = 2h+2
 *   kdtree_bounds   photon order: the children's bounding boxes (atomic min/max on flipped
 *                   keys: min and max do not depend on the order they are applied in)
 *   kdtree_finish   once a level's subtrees are small, each is finished by one work-item.
 * The split axis of a subtree is the axis of largest float extent max − min, ties x, y, z. */
#include "shared/types.h"

#define PCL_KD_DONE 0xFFFFFFFFu
#ifndef PCL_KD_FINISH
#define PCL_KD_FINISH 128u  /* subtrees of at most this many photons finish in one work-item */
#endif

/* The order-preserving float → uint flip of the sort (README, "sort"). */
static inline uint kd_float_key(float x) {
    const uint b = as_uint(x);
    return (b & 0x80000000u) ? ~b : (b ^ 0x80000000u);
}
static inline float kd_key_float(uint k) { return as_float((k & 0x80000000u) ? (k ^ 0x80000000u) : ~k); }

static inline float kd_coord(__global const PclPhoton* p, uint axis) {
    return axis == 0u ? p->x : (axis == 1u ? p->y : p->z);
}

static inline uint kd_axis_of(uint lx, uint ly, uint lz, uint hx, uint hy, uint hz) {
    const float ex = kd_key_float(hx) - kd_key_float(lx);
    const float ey = kd_key_float(hy) - kd_key_float(ly);
    const float ez = kd_key_float(hz) - kd_key_float(lz);
    uint axis = 0u;
    float e = ex;
    if (ey > e) { axis = 1u; e = ey; }
    if (ez > e) axis = 2u;
    return axis;
}

/* bounds[h*6 + a] = min key on axis a, bounds[h*6 + 3 + a] = max key. */
static inline uint kd_axis(__global const uint* bounds, uint h) {
    __global const uint* b = bounds + (size_t)h * 6u;
    return kd_axis_of(b[0], b[1], b[2], b[3], b[4], b[5]);
}

/* Left-balanced median: the size of the left subtree of a complete binary tree of n nodes. */
static inline uint kd_left_size(uint n) {
    if (n <= 1u) return 0u;
    const uint h = 31u - clz(n);  /* full levels above the last */
    const uint halfLevel = 1u << (h - 1u);
    return halfLevel - 1u + min(halfLevel, n - ((1u << h) - 1u));
}

__kernel void kdtree_init(uint n, __global uint* sub) {
    const uint i = (uint)get_global_id(0);
    if (i >= n) return;
    sub[i] = 0u;
}

__kernel void kdtree_bounds_init(__global uint* bounds, uint first, uint count) {
    const uint j = (uint)get_global_id(0);
    if (j >= count) return;
    __global uint* b = bounds + (size_t)(first + j) * 6u;
    b[0] = b[1] = b[2] = 0xFFFFFFFFu;
    b[3] = b[4] = b[5] = 0u;
}

/* Photon order: each photon's coordinates into its subtree's box. Read first, atomic only when
 * the photon extends the box: after the first few photons of a subtree almost none does, so the
 * pass is sequential reads, a cached read of the box and rare atomics. min and max do not
 * depend on the order they are applied in, so the box is exact and deterministic. */
static inline void kd_extend(volatile __global uint* b, uint a, uint k) {
    if (k < b[a]) atomic_min(b + a, k);
    if (k > b[3u + a]) atomic_max(b + 3u + a, k);
}

__kernel void kdtree_bounds(__global const PclPhoton* photons, __global const uint* sub, uint n,
                            __global uint* bounds) {
    const uint i = (uint)get_global_id(0);
    if (i >= n) return;
    const uint h = sub[i];
    if (h == PCL_KD_DONE) return;
    __global const PclPhoton* p = photons + i;
    volatile __global uint* b = (volatile __global uint*)(bounds + (size_t)h * 6u);
    kd_extend(b, 0u, kd_float_key(p->x));
    kd_extend(b, 1u, kd_float_key(p->y));
    kd_extend(b, 2u, kd_float_key(p->z));
}

/* Ranks: rank_a[i] = position of photon i when the map is ordered by (coordinate key on axis
 * a, photon index) — one stable radix sort per axis, once. Ordering a subtree by rank is
 * ordering it by (key, index), in rankBits = ⌈log2 n⌉ bits instead of 32 + a tie rule. */
__kernel void kdtree_rank_keys(__global const PclPhoton* photons, uint n, uint axis, __global uint* keys,
                               __global uint* values) {
    const uint i = (uint)get_global_id(0);
    if (i >= n) return;
    keys[i] = kd_float_key(kd_coord(photons + i, axis));
    values[i] = i;
}

__kernel void kdtree_rank_scatter(__global const uint* values, uint n, uint axis, __global uint* ranks) {
    const uint k = (uint)get_global_id(0);
    if (k >= n) return;
    ranks[(size_t)axis * n + values[k]] = k;
}

/* Keys of 32 bits while rankBits + level bits fit, else 64 (-DPCL_KD_KEY64=1). */
#ifndef PCL_KD_KEY64
#define PCL_KD_KEY64 0
#endif
#if PCL_KD_KEY64
typedef ulong kd_key;
#else
typedef uint kd_key;
#endif

/* ranks: axis-major, ranks[a*n + i]. */
__kernel void kdtree_keys(__global const uint* ranks, __global const uint* sub, uint n,
                          __global const uint* bounds, uint levelFirst, uint levelCount, uint rankBits,
                          __global kd_key* keys, __global uint* values) {
    const uint i = (uint)get_global_id(0);
    if (i >= n) return;
    const uint h = sub[i];
    kd_key key;
    if (h == PCL_KD_DONE) {
        key = (kd_key)levelCount << rankBits;
    } else {
        const uint axis = kd_axis(bounds, h);
        key = (kd_key)(h - levelFirst) << rankBits | (kd_key)ranks[(size_t)axis * n + i];
    }
    keys[i] = key;
    values[i] = i;
}

__kernel void kdtree_segments(__global const kd_key* keys, uint n, uint levelCount, uint rankBits,
                              __global uint* segStart, __global uint* segEnd) {
    const uint k = (uint)get_global_id(0);
    if (k >= n) return;
    const uint rel = (uint)(keys[k] >> rankBits);
    if (rel >= levelCount) return;
    if (k == 0u || (uint)(keys[k - 1u] >> rankBits) != rel) segStart[rel] = k;
    if (k == n - 1u || (uint)(keys[k + 1u] >> rankBits) != rel) segEnd[rel] = k + 1u;
}

__kernel void kdtree_assign(__global const PclPhoton* photons, __global const kd_key* keys,
                            __global const uint* values, uint n, uint levelFirst, uint levelCount, uint rankBits,
                            __global const uint* segStart, __global const uint* segEnd,
                            __global const uint* bounds, __global uint* sub, __global PclPhoton* tree,
                            __global uint* index) {
    const uint k = (uint)get_global_id(0);
    if (k >= n) return;
    const uint rel = (uint)(keys[k] >> rankBits);
    if (rel >= levelCount) return;
    const uint h = levelFirst + rel;
    const uint start = segStart[rel];
    const uint left = kd_left_size(segEnd[rel] - start);
    const uint r = k - start;
    const uint i = values[k];
    if (r == left) {
        PclPhoton p = photons[i];
        p.packed = (p.packed & ~PCL_PHOTON_AXIS_MASK) | (kd_axis(bounds, h) << PCL_PHOTON_AXIS_SHIFT);
        tree[h] = p;
        index[h] = i;
        sub[i] = PCL_KD_DONE;
    } else {
        sub[i] = r < left ? 2u * h + 1u : 2u * h + 2u;
    }
}

/* The last levels in one launch: once every subtree of a level holds at most PCL_KD_FINISH
 * photons (the host checks the largest, the level's leftmost), work-item rel builds the whole
 * subtree of node levelFirst + rel from its sorted segment by the same rule, depth first:
 * box, axis, photons ordered by (coordinate key, photon index) by insertion sort, the
 * left-balanced median the node. */
__kernel void kdtree_finish(__global const PclPhoton* photons, __global const uint* values,
                            __global const uint* segStart, __global const uint* segEnd, uint levelFirst,
                            uint levelCount, __global PclPhoton* tree, __global uint* index) {
    const uint rel = (uint)get_global_id(0);
    if (rel >= levelCount) return;
    const uint start = segStart[rel];
    const uint m = segEnd[rel] - start;
    uint idx[PCL_KD_FINISH], key[PCL_KD_FINISH];
    for (uint j = 0u; j < m; ++j) idx[j] = values[start + j];
    uint stackNode[32], stackBegin[32], stackEnd[32];
    uint top = 0u;
    stackNode[0] = levelFirst + rel;
    stackBegin[0] = 0u;
    stackEnd[0] = m;
    top = 1u;
    while (top > 0u) {
        --top;
        const uint h = stackNode[top], b = stackBegin[top], e = stackEnd[top];
        uint lo[3] = {0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu}, hi[3] = {0u, 0u, 0u};
        for (uint j = b; j < e; ++j) {
            __global const PclPhoton* p = photons + idx[j];
            const uint kx = kd_float_key(p->x), ky = kd_float_key(p->y), kz = kd_float_key(p->z);
            lo[0] = min(lo[0], kx); hi[0] = max(hi[0], kx);
            lo[1] = min(lo[1], ky); hi[1] = max(hi[1], ky);
            lo[2] = min(lo[2], kz); hi[2] = max(hi[2], kz);
        }
        const uint axis = kd_axis_of(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
        for (uint j = b; j < e; ++j) {
            const uint i = idx[j];
            const uint k = kd_float_key(kd_coord(photons + i, axis));
            uint t = j;
            while (t > b && (key[t - 1u] > k || (key[t - 1u] == k && idx[t - 1u] > i))) {
                key[t] = key[t - 1u];
                idx[t] = idx[t - 1u];
                --t;
            }
            key[t] = k;
            idx[t] = i;
        }
        const uint left = kd_left_size(e - b);
        const uint i = idx[b + left];
        PclPhoton p = photons[i];
        p.packed = (p.packed & ~PCL_PHOTON_AXIS_MASK) | (axis << PCL_PHOTON_AXIS_SHIFT);
        tree[h] = p;
        index[h] = i;
        if (b + left + 1u < e) {
            stackNode[top] = 2u * h + 2u;
            stackBegin[top] = b + left + 1u;
            stackEnd[top] = e;
            ++top;
        }
        if (left > 0u) {
            stackNode[top] = 2u * h + 1u;
            stackBegin[top] = b;
            stackEnd[top] = b + left;
            ++top;
        }
    }
}
