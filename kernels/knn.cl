/* knn.cl: the k nearest photons of each query (kernels/README.md, "Photon maps", knn; Jensen
 * 2001 §6.3, "locate photons" with a bounded max-heap), one query per work-item.
 *
 * knn_pack_kdtree  in: nodes[n] (photons in left-balanced heap order, split axis in bits 27..28
 *                    of packed), nodeIndex[n] (each node's photon index in the map), bucketFirst
 *                    out: packed[h] = (x, y, z, index | axis << 30) for the upper nodes h <
 *                    bucketFirst; then the buckets (below): n + 2 float4 in all
 * knn_kdtree    in:  packed nodes (upper nodes, then buckets), n, bucketFirst, firstRadius2 (a
 *                    first, tighter search bound; ∞: none), queries
 *
 * Buckets (shared/kd_buckets.h): the heap's last three levels are stored by subtree, compactly:
 * bucket b (root bucketFirst + b) holds its ≤ 7 existing nodes breadth first as four rows x, y,
 * z, w of `count` floats (w: index | axis << 30). The search descends the upper nodes one by one
 * as before and tests a reached bucket's nodes with float8 arithmetic at once (PoCL runs a
 * work-item as scalar code: explicit vectors are its SIMD, as in the traversal's float8 node
 * test). Testing a whole bucket offers a superset of the photons the node-by-node descent would
 * offer, so the result is the same (the k smallest by (d², index)).
 *
 * knn_hashgrid  in:  grid params, points[n] (float4 x, y, z, photon index bits, in (hash, index)
 *                    order), cellStart/cellEnd[tableSize], queries
 * out (both):   counts[q] ≤ k, indices[q·stride + j] and dist2[q·stride + j] for j < count in
 *               ascending (squared distance, photon index) order (PCL_NO_HIT, 0 past count),
 *               radius2[q] = the largest squared distance returned (0 if none).
 *
 * A query with maxRadius2 ≤ 0 is empty: it finds nothing and costs no search (the eye estimate's
 * records without a diffuse hit, or left to the caustic connections).
 * A candidate enters when d² ≤ maxRadius2 and (d², index) is below the heap's largest while the
 * heap is full: ties in distance go to the lower photon index, so every structure returns the
 * same set as the brute force. Squared distances are ((px−qx)² + (py−qy)²) + (pz−qz)² in float
 * without contraction: the brute-force twin computes the same bits.
 *
 * kd-tree pruning: a far subtree is skipped only when its splitting plane is strictly farther
 * (plane d² > the bound: maxRadius2, or the heap's largest d² once full) — with d² equal a far
 * photon of lower index could still enter. Float subtraction and addition are monotonic, so the
 * plane's d² never exceeds the d² of a photon beyond it.
 *
 * hash grid: the cells overlapping the query's box of half-width r' = r·(1 + 1e-4) + 1e-18
 * (r = √maxRadius2; the margin covers the rounding of the distance), at most 3 per axis
 * for r ≤ cellSize/2 (the host checks), nearest first; a cell whose box (less the margin) lies
 * beyond the heap's bound ends the search. Cells hashing to the same table entry are read once.
 *
 * PCL_KNN_CAP (-D, default PCL_KNN_MAX_K): heap capacity, ≥ every query's k. */
#pragma OPENCL FP_CONTRACT OFF
#include "shared/types.h"
#include "shared/hash_grid.h"
#include "shared/kd_buckets.h"

#ifndef PCL_KNN_CAP
#define PCL_KNN_CAP PCL_KNN_MAX_K
#endif
#define PCL_KNN_STACK 48

#define PCL_GRID_COORD_LIMIT 1.0e9f

/* A candidate as one 64-bit key: the bits of d² (≥ 0, so they order as the floats do) above
 * the photon index. (d², index) order is then one integer comparison. */
typedef struct KnnHeap {
    ulong key[PCL_KNN_CAP + 7]; /* + 7: knn_write pads a short heap to whole ulong8 blocks */
    uint n, k;
    float maxRadius2;
} KnnHeap;

inline ulong knn_key(float d, uint idx) { return (ulong)as_uint(d) << 32 | (ulong)idx; }
inline float knn_key_d2(ulong key) { return as_float((uint)(key >> 32)); }
inline uint knn_key_index(ulong key) { return (uint)key; }

/* The bound a candidate's (or a plane's) d² is compared with. */
inline float knn_bound(const KnnHeap* h) { return h->n < h->k ? h->maxRadius2 : knn_key_d2(h->key[0]); }

inline void knn_sift_down(KnnHeap* h, uint i, uint n) {
    const ulong key = h->key[i];
    for (;;) {
        uint c = 2u * i + 1u;
        if (c >= n) break;
        if (c + 1u < n && h->key[c + 1u] > h->key[c]) ++c;
        if (!(h->key[c] > key)) break;
        h->key[i] = h->key[c];
        i = c;
    }
    h->key[i] = key;
}

/* Bottom-up heap construction of the first n keys (O(n)). */
inline void knn_heapify(KnnHeap* h) {
    for (uint i = h->n / 2u; i > 0u; --i) knn_sift_down(h, i - 1u, h->n);
}

/* Until k candidates are in, they are only appended (the bound is maxRadius2 then, whatever
 * their order); the k-th makes the array a max-heap. The searches offer candidates roughly
 * nearest first, each the largest so far, which a heap insertion would sift up to the root. */
inline void knn_offer(KnnHeap* h, float d, uint idx) {
    if (!(d <= h->maxRadius2)) return;
    const ulong key = knn_key(d, idx);
    if (h->n < h->k) {
        h->key[h->n++] = key;
        if (h->n == h->k) knn_heapify(h);
    } else if (h->key[0] > key) {
        h->key[0] = key;
        knn_sift_down(h, 0u, h->n);
    }
}

inline void knn_init(KnnHeap* h, const PclKnnQuery q) {
    h->n = 0u;
    h->k = min(q.k, (uint)PCL_KNN_CAP);
    h->maxRadius2 = q.maxRadius2;
}

/* The query's outputs in ascending key order. The sorted keys depend only on the set found
 * (every key is distinct), not on the heap's arrangement. Up to PCL_KNN_RANK_MAX keys, each
 * goes straight to its rank, the number of keys below it, counted eight at a time with ulong8
 * compares (branch-free, where a heap sort's sift-downs branch unpredictably: knn_write fell
 * from 11 % of knn_bench's box/k50 samples to 5.5 %); beyond, a heap sort in place. */
#define PCL_KNN_RANK_MAX 64u
inline void knn_write(KnnHeap* h, uint q, uint stride, __global uint* counts, __global uint* indices,
                      __global float* dist2, __global float* radius2) {
    const size_t base = (size_t)q * stride;
    if (h->n <= PCL_KNN_RANK_MAX) {
        const uint n = h->n, blocks = (n + 7u) / 8u;
        for (uint j = n; j < 8u * blocks; ++j) h->key[j] = ULONG_MAX; /* above every key: never counted */
        for (uint i = 0u; i < n; ++i) {
            const ulong key = h->key[i];
            long8 below = (long8)(0);
            for (uint b = 0u; b < blocks; ++b) below += vload8(b, h->key) < (ulong8)(key); /* −1 per key below */
            const long4 b4 = below.lo + below.hi;
            const long2 b2 = b4.lo + b4.hi;
            const uint rank = (uint)(-(b2.x + b2.y));
            indices[base + rank] = knn_key_index(key);
            dist2[base + rank] = knn_key_d2(key);
            if (rank + 1u == n) radius2[q] = knn_key_d2(key);
        }
        for (uint j = n; j < stride; ++j) {
            indices[base + j] = PCL_NO_HIT;
            dist2[base + j] = 0.0f;
        }
        counts[q] = n;
        if (n == 0u) radius2[q] = 0.0f;
        return;
    }
    if (h->n < h->k) knn_heapify(h); /* fewer than k found: still in arrival order */
    for (uint end = h->n; end > 1u; --end) {
        const ulong top = h->key[0];
        h->key[0] = h->key[end - 1u];
        h->key[end - 1u] = top;
        knn_sift_down(h, 0u, end - 1u);
    }
    for (uint j = 0u; j < stride; ++j) {
        indices[base + j] = j < h->n ? knn_key_index(h->key[j]) : PCL_NO_HIT;
        dist2[base + j] = j < h->n ? knn_key_d2(h->key[j]) : 0.0f;
    }
    counts[q] = h->n;
    radius2[q] = h->n ? knn_key_d2(h->key[h->n - 1u]) : 0.0f;
}

inline float knn_dist2(float px, float py, float pz, float qx, float qy, float qz) {
    const float dx = px - qx, dy = py - qy, dz = pz - qz;
    return dx * dx + dy * dy + dz * dz;
}

/* The lanes of an 8-wide test that passed, as bits (lane l: bit l); knn_next_lane takes the
 * lowest one out. Only those lanes are visited, in lane order, as the loop over all eight
 * with a test each did (about one lane in eight passes). */
inline uint knn_lane_bits(int8 pass) {
    const int8 bit = pass & (int8)(1, 2, 4, 8, 16, 32, 64, 128);
    return (uint)(bit.s0 | bit.s1 | bit.s2 | bit.s3 | bit.s4 | bit.s5 | bit.s6 | bit.s7);
}

inline uint knn_next_lane(uint* bits) {
    const uint lane = 31u - clz(*bits & (0u - *bits));
    *bits &= *bits - 1u;
    return lane;
}

/* kd-tree nodes packed for the search: (x, y, z, photon index | axis << 30 as bits of w), one
 * 16-byte load per visited upper node; the buckets' rows after them. One work-item per node. */
__kernel void knn_pack_kdtree(__global const PclPhoton* nodes, __global const uint* nodeIndex, uint n,
                              uint bucketFirst, __global float4* packed) {
    const uint h = (uint)get_global_id(0);
    if (h >= n) return;
    const PclPhoton p = nodes[h];
    const uint axis = (p.packed & PCL_PHOTON_AXIS_MASK) >> PCL_PHOTON_AXIS_SHIFT;
    const uint w = nodeIndex[h] | (axis << 30);
    if (h < bucketFirst) {
        packed[h] = (float4)(p.x, p.y, p.z, as_float(w));
        return;
    }
    uint b, s;
    kd_bucket_slot(h, bucketFirst, &b, &s);
    const uint count = kd_bucket_count(n, bucketFirst, b);
    __global float* row = (__global float*)(packed + bucketFirst) + (size_t)4u * kd_bucket_offset(n, bucketFirst, b) + s;
    row[0] = p.x, row[count] = p.y, row[2u * count] = p.z, row[3u * count] = as_float(w);
}

/* A bucket's nodes against the query, then each accepted one into the heap in slot order. */
inline void knn_offer_bucket(KnnHeap* h, __global const float4* nodes, uint n, uint bucketFirst, uint bucket, float qx,
                             float qy, float qz) {
    const uint count = kd_bucket_count(n, bucketFirst, bucket);
    __global const float* row = (__global const float*)(nodes + bucketFirst) +
                                (size_t)4u * kd_bucket_offset(n, bucketFirst, bucket);
    const float8 dx = vload8(0, row) - (float8)(qx), dy = vload8(0, row + count) - (float8)(qy),
                 dz = vload8(0, row + 2u * count) - (float8)(qz);
    const float8 d = (dx * dx + dy * dy) + dz * dz;
    const int8 lanes = (int8)(0, 1, 2, 3, 4, 5, 6, 7);
    const int8 near = (lanes < (int8)((int)count)) & (d <= (float8)(knn_bound(h)));
    if (!any(near)) return;
    uint bits = knn_lane_bits(near);
    const uint8 w = as_uint8(vload8(0, row + 3u * count));
    const float dd[8] = {d.s0, d.s1, d.s2, d.s3, d.s4, d.s5, d.s6, d.s7};
    const uint ww[8] = {w.s0, w.s1, w.s2, w.s3, w.s4, w.s5, w.s6, w.s7};
    while (bits) {
        const uint s = knn_next_lane(&bits);
        if (dd[s] <= knn_bound(h)) knn_offer(h, dd[s], ww[s] & 0x3FFFFFFFu);
    }
}

/* The kd-tree descent: every photon within the heap's bound offered. */
inline void knn_kdtree_search(KnnHeap* h, __global const float4* nodes, uint n, uint bucketFirst, const PclKnnQuery q) {
    uint stackNode[PCL_KNN_STACK];
    float stackD[PCL_KNN_STACK];
    uint sp = 0u;
    uint node = (n > 0u && h->k > 0u) ? 0u : n;
    for (;;) {
        while (node < n) {
            if (node >= bucketFirst) {
                knn_offer_bucket(h, nodes, n, bucketFirst, node - bucketFirst, q.x, q.y, q.z);
                break;
            }
            const float4 p = nodes[node];
            const uint w = as_uint(p.w);
            const uint axis = w >> 30;
            const float diff = axis == 0u ? q.x - p.x : (axis == 1u ? q.y - p.y : q.z - p.z);
            const uint left = 2u * node + 1u;
            const uint nearChild = diff < 0.0f ? left : left + 1u;
            const uint farChild = diff < 0.0f ? left + 1u : left;
            const float planeD2 = diff * diff;
            if (farChild < n && planeD2 <= knn_bound(h)) {
                stackNode[sp] = farChild;
                stackD[sp] = planeD2;
                ++sp;
            }
            const float d = knn_dist2(p.x, p.y, p.z, q.x, q.y, q.z);
            if (d <= knn_bound(h)) knn_offer(h, d, w & 0x3FFFFFFFu);
            node = nearChild;
        }
        node = n;
        while (sp > 0u) {
            --sp;
            if (stackD[sp] <= knn_bound(h)) {
                node = stackNode[sp];
                break;
            }
        }
        if (node >= n) break;
    }
}

/* firstRadius2: a first search within min(maxRadius2, firstRadius2) (a guess of the k-th
 * photon's d² from the map's mean density, pipeline/estimate.h): until the heap is full every
 * photon under the bound enters it, so a tight first bound saves most heap work. When it finds
 * k photons those are the k nearest within maxRadius2 (every other photon is farther); when it
 * finds fewer the search runs again with maxRadius2. The result is the same either way. */
__kernel void knn_kdtree(__global const float4* nodes, uint n, uint bucketFirst, float firstRadius2,
                         __global const PclKnnQuery* queries, uint queryCount, uint stride, __global uint* counts,
                         __global uint* indices, __global float* dist2, __global float* radius2) {
    const uint qi = (uint)get_global_id(0);
    if (qi >= queryCount) return;
    const PclKnnQuery q = queries[qi];
    KnnHeap h;
    knn_init(&h, q);
    if (!(q.maxRadius2 > 0.0f)) {
        /* empty: nothing */
    } else if (firstRadius2 < h.maxRadius2) {
        h.maxRadius2 = firstRadius2;
        knn_kdtree_search(&h, nodes, n, bucketFirst, q);
        if (h.n < h.k) {
            knn_init(&h, q);
            knn_kdtree_search(&h, nodes, n, bucketFirst, q);
        }
    } else {
        knn_kdtree_search(&h, nodes, n, bucketFirst, q);
    }
    knn_write(&h, qi, stride, counts, indices, dist2, radius2);
}

/* A cell's run of points [s, end), eight at a time: their d² with float8 arithmetic (the same
 * bits per lane as knn_dist2), then the lanes within the bound offered in order; the last < 8
 * one by one (no read past the run's end). */
inline void knn_offer_run(KnnHeap* h, __global const float4* points, uint s, uint end, float qx, float qy, float qz) {
    for (; s + 8u <= end; s += 8u) {
        const float16 a = vload16(0, (__global const float*)(points + s));
        const float16 b = vload16(0, (__global const float*)(points + s + 4u));
        const float8 dx = (float8)(a.s048c, b.s048c) - (float8)(qx), dy = (float8)(a.s159d, b.s159d) - (float8)(qy),
                     dz = (float8)(a.s26ae, b.s26ae) - (float8)(qz);
        const float8 d = (dx * dx + dy * dy) + dz * dz;
        const int8 near = d <= (float8)(knn_bound(h));
        if (!any(near)) continue;
        uint bits = knn_lane_bits(near);
        const uint8 w = as_uint8((float8)(a.s37bf, b.s37bf));
        const float dd[8] = {d.s0, d.s1, d.s2, d.s3, d.s4, d.s5, d.s6, d.s7};
        const uint ww[8] = {w.s0, w.s1, w.s2, w.s3, w.s4, w.s5, w.s6, w.s7};
        while (bits) {
            const uint l = knn_next_lane(&bits);
            if (dd[l] <= knn_bound(h)) knn_offer(h, dd[l], ww[l]);
        }
    }
    for (; s < end; ++s) {
        const float4 p = points[s];
        const float d = knn_dist2(p.x, p.y, p.z, qx, qy, qz);
        if (d <= knn_bound(h)) knn_offer(h, d, as_uint(p.w));
    }
}

__kernel void knn_hashgrid(const PclGridParams g, __global const float4* points, __global const uint* cellStart,
                           __global const uint* cellEnd, __global const PclKnnQuery* queries, uint queryCount,
                           uint stride, __global uint* counts, __global uint* indices, __global float* dist2,
                           __global float* radius2) {
    const uint qi = (uint)get_global_id(0);
    if (qi >= queryCount) return;
    const PclKnnQuery q = queries[qi];
    KnnHeap h;
    knn_init(&h, q);
    if (g.photonCount > 0u && h.k > 0u && q.maxRadius2 > 0.0f) {
        /* Window: rounding is monotonic, so a photon p with d² ≤ maxRadius2 (true |p − q| <
         * r·(1 + 1e-6)) has a cell coordinate ≥ that of q − r' whenever r' exceeds that: the
         * relative 1e-4 suffices, the 1e-18 covers d² underflowing for tiny differences. */
        const float r = sqrt(q.maxRadius2) * 1.0001f + 1e-18f;
        const float scale = fmax(fmax(fabs(q.x), fabs(q.y)), fabs(q.z)) + fmax(fmax(fabs(g.ox), fabs(g.oy)), fabs(g.oz));
        const int x0 = hash_grid_coord(q.x - r, g.ox, g.invCellSize), x1 = hash_grid_coord(q.x + r, g.ox, g.invCellSize);
        const int y0 = hash_grid_coord(q.y - r, g.oy, g.invCellSize), y1 = hash_grid_coord(q.y + r, g.oy, g.invCellSize);
        const int z0 = hash_grid_coord(q.z - r, g.oz, g.invCellSize), z1 = hash_grid_coord(q.z + r, g.oz, g.invCellSize);
        /* The cells nearest first, each with a lower bound of its photons' d²: the gap from q to
         * the cell's box in float, less a margin for the rounding of the box (o + ix·cellSize)
         * and of the photons' cell coordinates, ≤ 4e-7 (|p| + |o|). Once that bound exceeds the
         * heap's, no later cell can add anything. Photons of other cells sharing a hash are
         * filtered by d² as they are read. */
        uint cellHash[27];
        float cellD2[27];
        uint cells = 0u;
        const float margin = (r - sqrt(q.maxRadius2)) + 1e-6f * (scale + r);
        for (int iz = z0; iz <= z1 && iz <= z0 + 2; ++iz)
            for (int iy = y0; iy <= y1 && iy <= y0 + 2; ++iy)
                for (int ix = x0; ix <= x1 && ix <= x0 + 2; ++ix) {
                    const float lo[3] = {g.ox + (float)ix * g.cellSize, g.oy + (float)iy * g.cellSize,
                                         g.oz + (float)iz * g.cellSize};
                    const float qc[3] = {q.x, q.y, q.z};
                    const int ic[3] = {ix, iy, iz};
                    float d2 = 0.0f;
                    for (int a = 0; a < 3; ++a) {
                        /* a clamped coordinate's cell holds photons from beyond it: no bound there */
                        const bool clamped = ic[a] >= (int)PCL_GRID_COORD_LIMIT || ic[a] <= -(int)PCL_GRID_COORD_LIMIT;
                        const float gap =
                            clamped ? 0.0f : fmax(fmax(lo[a] - qc[a], qc[a] - (lo[a] + g.cellSize)), 0.0f);
                        const float shrunk = fmax(gap - margin, 0.0f);
                        d2 += shrunk * shrunk;
                    }
                    cellHash[cells] = hash_grid_hash(ix, iy, iz, g.tableSize);
                    cellD2[cells] = d2;
                    ++cells;
                }
        /* Every cell's range read before any is scanned: the table reads are independent of
         * each other and of the heap, so their cache misses overlap instead of each stalling
         * between two scans (+8 % queries per CPU-second, knn_bench box/k50, 5 interleaved runs;
         * prefetch() of each run's first points as well gained nothing more). */
        uint cellFirst[27], cellLast[27];
        for (uint c = 0u; c < cells; ++c) {
            cellFirst[c] = cellStart[cellHash[c]];
            cellLast[c] = cellEnd[cellHash[c]];
        }
        for (uint visited = 0u; visited < cells; ++visited) {
            uint best = visited;
            for (uint c = visited + 1u; c < cells; ++c)
                if (cellD2[c] < cellD2[best]) best = c;
            const uint cell = cellHash[best];
            const float boxD2 = cellD2[best];
            const uint first = cellFirst[best], last = cellLast[best];
            cellHash[best] = cellHash[visited];
            cellD2[best] = cellD2[visited];
            cellFirst[best] = cellFirst[visited];
            cellLast[best] = cellLast[visited];
            if (boxD2 > knn_bound(&h)) break;
            bool dup = false;
            for (uint c = 0u; c < visited; ++c) dup = dup || cellHash[c] == cell;
            cellHash[visited] = cell;  /* visited cells keep their hash for the duplicate test */
            if (dup) continue;
            knn_offer_run(&h, points, first, last, q.x, q.y, q.z);
        }
    }
    knn_write(&h, qi, stride, counts, indices, dist2, radius2);
}
