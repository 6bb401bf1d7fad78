/* kdtree.cl: Jensen's left-balanced kd-tree built on the device by stable partitions of three
 * sorted lists (kernels/README.md, "Photon maps", kd-tree; Jensen 2001 §6.3). The tree is a
 * heap over the photon array: node h has children 2h+1 and 2h+2, split axis in bits 27..28 of
 * `packed`.
 *
 * Lists: for each axis a, the map's photons as uint4 (key x, key y, key z, photon index) ordered
 * by (key on a, photon index) — one stable radix sort per axis, once (kdtree_points, then
 * per axis the sort and kdtree_lists). Two sets of three lists each (x0, y0, z0 and x1, y1, z1).
 * The photons of the subtree of node h occupy the same range [start, end) of all three lists,
 * each list ordered by its axis; nodes[h] = (start, end, mask): list a of the subtree lies in
 * buffer (mask >> a) & 1.
 *
 * Splitting a subtree: its box is read off the ends of its lists (first and last key of list a
 * on axis a), the axis is the largest float extent max − min (ties x, y, z), the node the photon
 * at start + left(n) of the axis' list, and every list is split stably into [left | node | right]
 * by comparing (key on the axis, index) with the node's: list `axis` already is, the other two
 * are written into the other buffer (so the children's mask flips their two bits). The order of
 * each list is kept, so the children's lists are ordered again and no level sorts.
 *   kdtree_count    large subtrees (a level at a time): each subtree's range cut into chunks, one
 *                   work-item per chunk counts the photons going left (and the node) in each
 *                   of the two lists; work-item 0 of a subtree records the node and its children's ranges
 *   kdtree_scatter  the same chunks: the counts of the subtree's earlier chunks give each
 *                   photon its place in the other buffer
 *   kdtree_finish   once a level's subtrees are small, one work-item per subtree builds the
 *                   rest of it depth first by sequential partitions
 *   kdtree_places,  the splits record each node's photon index and axis; two last passes copy
 *   kdtree_nodes    the photons into heap order. */
#include "shared/types.h"

/* The order-preserving float → uint flip of the sort (README, "sort"). */
static inline uint kd_float_key(float x) {
    const uint b = as_uint(x);
    return (b & 0x80000000u) ? ~b : (b ^ 0x80000000u);
}
static inline float kd_key_float(uint k) { return as_float((k & 0x80000000u) ? (k ^ 0x80000000u) : ~k); }

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

/* Left-balanced median: the size of the left subtree of a complete binary tree of n nodes. */
static inline uint kd_left_size(uint n) {
    if (n <= 1u) return 0u;
    const uint h = 31u - clz(n);  /* full levels above the last */
    const uint halfLevel = 1u << (h - 1u);
    return halfLevel - 1u + min(halfLevel, n - ((1u << h) - 1u));
}

static inline uint kd_component(uint4 v, uint axis) { return axis == 0u ? v.x : (axis == 1u ? v.y : v.z); }

/* The (key on the axis, photon index) order as one 64-bit number: a photon goes left of the node
 * when its number is smaller, and is the node when equal (comparisons without branches). */
static inline ulong kd_order(uint4 v, uint axis) { return (ulong)kd_component(v, axis) << 32 | (ulong)v.w; }

/* The six lists as kernel arguments (one buffer each: none larger than the photon map). */
#define KD_LISTS                                                                                     \
    __global uint4 *x0, __global uint4 *y0, __global uint4 *z0, __global uint4 *x1, __global uint4 *y1, \
        __global uint4 *z1
#define KD_LISTS_ARGS x0, y0, z0, x1, y1, z1

static inline __global uint4* kd_list(KD_LISTS, uint mask, uint axis, uint flip) {
    const uint b = ((mask >> axis) & 1u) ^ flip;
    return axis == 0u ? (b ? x1 : x0) : (axis == 1u ? (b ? y1 : y0) : (b ? z1 : z0));
}

/* The split of the subtree in [s, e): returns the axis; *left = left(e − s), *node = the node's
 * list element. */
static inline uint kd_split(KD_LISTS, uint s, uint e, uint mask, uint* left, uint4* node) {
    __global const uint4* lx = kd_list(KD_LISTS_ARGS, mask, 0u, 0u);
    __global const uint4* ly = kd_list(KD_LISTS_ARGS, mask, 1u, 0u);
    __global const uint4* lz = kd_list(KD_LISTS_ARGS, mask, 2u, 0u);
    const uint axis = kd_axis_of(lx[s].x, ly[s].y, lz[s].z, lx[e - 1u].x, ly[e - 1u].y, lz[e - 1u].z);
    *left = kd_left_size(e - s);
    *node = kd_list(KD_LISTS_ARGS, mask, axis, 0u)[s + *left];
    return axis;
}

/* Node h is photon i, split on the axis: recorded here, the photon copied by kdtree_nodes (one
 * pass of independent accesses, instead of a cache miss in the middle of every split). */
static inline void kd_emit(uint h, uint i, uint axis, __global uint* index, __global uchar* axes) {
    index[h] = i;
    axes[h] = (uchar)axis;
}

/* The children's mask: the two lists other than the axis' move to the other buffer. */
static inline uint kd_child_mask(uint mask, uint axis) { return mask ^ (7u & ~(1u << axis)); }

/* The list element of each photon, in map order (points: list x1, free until the
 * first split), and the first rank sort's input (key on x, photon index). */
__kernel void kdtree_points(__global const PclPhoton* photons, uint n, __global uint4* points, __global uint* keys,
                            __global uint* values) {
    const uint i = (uint)get_global_id(0);
    if (i >= n) return;
    __global const PclPhoton* p = photons + i;
    const uint4 v = (uint4)(kd_float_key(p->x), kd_float_key(p->y), kd_float_key(p->z), i);
    points[i] = v;
    keys[i] = v.x;
    values[i] = i;
}

/* After the stable sort on the axis: list `axis` of buffer 0 in (key, index) order, and the
 * next sort's input (key on axis + 1, photon index; each work-item reads its pair before
 * writing it); the root's range. */
__kernel void kdtree_lists(__global const uint4* points, __global uint* keys, __global uint* values, uint n, uint axis,
                           __global uint4* x0, __global uint4* y0, __global uint4* z0, __global uint4* nodes) {
    const uint k = (uint)get_global_id(0);
    if (k >= n) return;
    (axis == 0u ? x0 : (axis == 1u ? y0 : z0))[k] = points[values[k]];
    if (axis < 2u) {
        keys[k] = kd_component(points[k], axis + 1u);
        values[k] = k;
    }
    if (k == 0u && axis == 0u) nodes[0] = (uint4)(0u, n, 0u, 0u);
}

/* Work-item j of a level: chunk j % chunks of the level's subtree j / chunks, the range
 * [s + c·chunk, min(s + (c + 1)·chunk, e)). counts[2j + o] (o = 0, 1: the lists axis + 1,
 * axis + 2 mod 3) = 2 × (photons before the node) + (1 if the node is in the chunk). */
/* src[from, to) copied to dst stably in three parts: photons ordered before the node on `axis`
 * to lp, lp + 1, ..., those after it to rp, rp + 1, ..., the node itself to nodePos. */
static inline void kd_partition(__global const uint4* src, __global uint4* dst, uint from, uint to, uint axis,
                                ulong nodeOrder, uint nodePos, uint lp, uint rp) {
    for (uint k = from; k < to; ++k) {
        const uint4 v = src[k];
        const ulong order = kd_order(v, axis);
        const uint isLeft = (uint)(order < nodeOrder), isRight = (uint)(order > nodeOrder);
        dst[select(select(nodePos, rp, isRight), lp, isLeft)] = v;
        lp += isLeft;
        rp += isRight;
    }
}

/* Work-item j of a level's count or scatter pass: chunk c of the subtree of node h = first +
 * j / chunks, whose photons are [s, e) of its lists (mask: which copy holds each), its split
 * (axis, left size, node), and the chunk's own range [lo, hi). */
typedef struct {
    uint c, h, s, e, mask, axis, left, lo, hi;
    uint4 node;
} KdChunk;

static inline KdChunk kd_chunk(KD_LISTS, __global const uint4* nodes, uint first, uint chunks, uint chunk, uint j) {
    KdChunk k;
    const uint rel = j / chunks;
    k.c = j - rel * chunks;
    k.h = first + rel;
    const uint4 nd = nodes[k.h];
    k.s = nd.x;
    k.e = nd.y;
    k.mask = nd.z;
    k.axis = kd_split(KD_LISTS_ARGS, k.s, k.e, k.mask, &k.left, &k.node);
    k.lo = min(k.s + k.c * chunk, k.e);
    k.hi = min(k.lo + chunk, k.e);
    return k;
}

__kernel void kdtree_count(KD_LISTS, __global uint4* nodes, uint first, uint count, uint chunks, uint chunk,
                           __global uint* counts, __global uint* index, __global uchar* axes) {
    const uint j = (uint)get_global_id(0);
    if (j >= count * chunks) return;
    const KdChunk ck = kd_chunk(KD_LISTS_ARGS, nodes, first, chunks, chunk, j);
    const uint c = ck.c, h = ck.h, s = ck.s, e = ck.e, mask = ck.mask, axis = ck.axis, left = ck.left;
    const uint4 node = ck.node;
    if (c == 0u) {
        kd_emit(h, node.w, axis, index, axes);
        const uint cm = kd_child_mask(mask, axis);
        if (left > 0u) nodes[2u * h + 1u] = (uint4)(s, s + left, cm, 0u);
        if (s + left + 1u < e) nodes[2u * h + 2u] = (uint4)(s + left + 1u, e, cm, 0u);
    }
    const uint lo = ck.lo, hi = ck.hi;
    for (uint o = 0u; o < 2u; ++o) {
        const uint a = (axis + 1u + o) % 3u;
        __global const uint4* src = kd_list(KD_LISTS_ARGS, mask, a, 0u);
        const ulong nodeOrder = kd_order(node, axis);
        uint sum = 0u;
        for (uint k = lo; k < hi; ++k) {
            const ulong order = kd_order(src[k], axis);
            sum += ((uint)(order < nodeOrder) << 1) + (uint)(order == nodeOrder);
        }
        counts[2u * j + o] = sum;
    }
}

__kernel void kdtree_scatter(KD_LISTS, __global const uint4* nodes, uint first, uint count, uint chunks, uint chunk,
                             __global const uint* counts) {
    const uint j = (uint)get_global_id(0);
    if (j >= count * chunks) return;
    const KdChunk ck = kd_chunk(KD_LISTS_ARGS, nodes, first, chunks, chunk, j);
    const uint c = ck.c, s = ck.s, mask = ck.mask, axis = ck.axis, left = ck.left, lo = ck.lo, hi = ck.hi;
    const uint4 node = ck.node;
    if (lo >= hi) return;
    for (uint o = 0u; o < 2u; ++o) {
        const uint a = (axis + 1u + o) % 3u;
        __global const uint4* src = kd_list(KD_LISTS_ARGS, mask, a, 0u);
        __global uint4* dst = kd_list(KD_LISTS_ARGS, mask, a, 1u);
        uint before = 0u;
        for (uint t = j - c; t < j; ++t) before += counts[2u * t + o];
        const ulong nodeOrder = kd_order(node, axis);
        /* the next places left and right of the node: past those of the subtree's earlier chunks */
        const uint lp = s + (before >> 1);
        const uint rp = s + left + 1u + (lo - s - (before >> 1) - (before & 1u));
        kd_partition(src, dst, lo, hi, axis, nodeOrder, s + left, lp, rp);
    }
}

/* The last levels in one launch: once every subtree of a level holds at most finishSize photons
 * (the host checks the largest, the level's leftmost), work-item rel builds the whole subtree of
 * node first + rel, depth first, by the same rule, partitioning its lists sequentially. */
__kernel void kdtree_finish(KD_LISTS, __global const uint4* nodes, uint first, uint count, __global uint* index,
                            __global uchar* axes) {
    const uint rel = (uint)get_global_id(0);
    if (rel >= count) return;
    uint4 stack[32];  /* (node, start, end, mask); depth ≤ 31 */
    const uint4 root = nodes[first + rel];
    stack[0] = (uint4)(first + rel, root.x, root.y, root.z);
    uint top = 1u;
    while (top > 0u) {
        const uint4 t = stack[--top];
        const uint h = t.x, s = t.y, e = t.z, mask = t.w;
        if (e - s == 1u) {  /* a leaf: its box is a point, axis x */
            kd_emit(h, kd_list(KD_LISTS_ARGS, mask, 0u, 0u)[s].w, 0u, index, axes);
            continue;
        }
        uint left;
        uint4 node;
        const uint axis = kd_split(KD_LISTS_ARGS, s, e, mask, &left, &node);
        kd_emit(h, node.w, axis, index, axes);
        if (e - s <= 3u) {  /* one or two leaves, read off the axis' list */
            __global const uint4* l = kd_list(KD_LISTS_ARGS, mask, axis, 0u);
            kd_emit(2u * h + 1u, l[s].w, 0u, index, axes);
            if (e - s == 3u) kd_emit(2u * h + 2u, l[s + 2u].w, 0u, index, axes);
            continue;
        }
        for (uint o = 0u; o < 2u; ++o) {
            const uint a = (axis + 1u + o) % 3u;
            __global const uint4* src = kd_list(KD_LISTS_ARGS, mask, a, 0u);
            __global uint4* dst = kd_list(KD_LISTS_ARGS, mask, a, 1u);
            const ulong nodeOrder = kd_order(node, axis);
            kd_partition(src, dst, s, e, axis, nodeOrder, s + left, s, s + left + 1u);
        }
        const uint cm = kd_child_mask(mask, axis);
        if (s + left + 1u < e) stack[top++] = (uint4)(2u * h + 2u, s + left + 1u, e, cm);
        stack[top++] = (uint4)(2u * h + 1u, s, s + left, cm);  /* left ≥ 1 for e − s ≥ 2 */
    }
}

/* The tree: node h = photon index[h] with its split axis, written photon by photon (reads in
 * order, stores scattered: they do not hold the core up the way scattered reads do).
 * kdtree_places: place[index[h]] = h. */
__kernel void kdtree_places(__global const uint* index, uint n, __global uint* place) {
    const uint h = (uint)get_global_id(0);
    if (h >= n) return;
    place[index[h]] = h;
}

__kernel void kdtree_nodes(__global const PclPhoton* photons, __global const uint* place,
                           __global const uchar* axes, uint n, __global PclPhoton* tree) {
    const uint i = (uint)get_global_id(0);
    if (i >= n) return;
    const uint h = place[i];
    PclPhoton p = photons[i];
    p.packed = (p.packed & ~PCL_PHOTON_AXIS_MASK) | ((uint)axes[h] << PCL_PHOTON_AXIS_SHIFT);
    tree[h] = p;
}
