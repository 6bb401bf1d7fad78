/* precomputed_irradiance.cl: Christensen's precomputed irradiance (Christensen 1999, "Faster
 * Photon Map Global Illumination"; kernels/README.md, "precomputed irradiance"): the irradiance
 * is estimated once at every m-th photon of the global map and stored with it, so a later
 * lookup is one nearest-neighbour search instead of a k-nearest-neighbour estimate.
 *
 * precomputed_irradiance_select  in:  photons[n] (the global map in deposit order), every = m ≥ 2
 *                                out: points[j] for j < ⌈n/m⌉: photon j·m's position and normal
 *                                     word, photon = j·m, irradiance 0; queries[j]: the estimate's
 *                                     query at that photon (its decoded normal, maxRadius2, k)
 * precomputed_irradiance_unselected  in: photons[n], every = m
 *                                out: others[i − ⌊i/m⌋ − 1] = photon i for every i not a multiple
 *                                     of m (deposit order kept): the map the estimates search
 * precomputed_irradiance_store   in:  estimates[s] (PclEstimate of query order[s] = point j in the
 *                                     others; the queries ran in pipeline/query_order's order), order,
 *                                     scale = (float)m / (float)(m − 1), coverScale2 = f² (f: the
 *                                     cover radius over the estimate's radius)
 *                                out: points[j].r, g, b = estimate · scale; cover[j] =
 *                                     coverScale2 · the estimate's r² (∞ when coverScale2 is ∞);
 *                                     nondirect[j] = the estimate's nondirect RGBE decoded · scale
 *                                     (the photons of bounce > 0 alone)
 * precomputed_irradiance_as_photons  in: points[n]  out: photons[n] with the points' x, y, z and
 *                                     normal (rgbe, packed 0): what the kd-tree builder sorts
 * precomputed_irradiance_pack    in:  the kd-tree of those photons (heap order, split axis in bits
 *                                     27..28 of packed), index[h] (heap position → point), points, cover,
 *                                     nondirect
 *                                out: nodes[h] = points[index[h]], split axis in bits 30..31 of
 *                                     photon; nodeCover[h] = cover[index[h]]; nodeNondirect[h] =
 *                                     nondirect[index[h]]
 * precomputed_irradiance_buckets in: nodes[n], nodeCover[n], bucketFirst (pipeline/knn.h
 *                                     knnBucketFirst)
 *                                out: buckets: the tree's last three levels by subtree as in
 *                                     knn.cl (shared/kd_buckets.h), nine rows per bucket: x, y,
 *                                     z, cover, decoded normal x, y, z, then photon index and
 *                                     heap node (uint bits)
 * precomputed_irradiance_lookup  in:  nodes[n], nodeCover[n], nodeNondirect[n] (the packed tree), bucketFirst,
 *                                     buckets, queries[q], minNormalCos, zeroRadiusIsNone (1: a
 *                                     query with maxRadius2 = 0 is no query, answered "none"
 *                                     without a search: the final gather's rays without a
 *                                     diffuse hit, a third of cornell-box's; 0: it finds a point
 *                                     at d² = 0)
 *                                out: irradiance[q] = (r, g, b, d²) of the nearest node within
 *                                     maxRadius2 that covers the query and whose normal agrees
 *                                     (r, g, b from nodeNondirect when the query's k has
 *                                     PCL_QUERY_NONDIRECT),
 *                                     (0, 0, 0, 0) when none; chosen[q] = its photon index,
 *                                     PCL_NO_HIT when none
 *
 * The lookup is Jensen's nearest-photon descent with k = 1: a candidate is taken when
 * d² ≤ maxRadius2, (d², photon index) is below the best so far (ties go to the lower photon
 * index), the query lies in the point's cover (d² ≤ nodeCover, f = 2 times the radius its
 * estimate was made over: a stored value does not answer for places far beyond its photons, such
 * as a dark floor next to a lit one) and its normal agrees: n_p·n_q ≥ minNormalCos with n_p =
 * photon_normal_decode(word) and the dot ((n_p.x q.nx + n_p.y q.ny) + n_p.z q.nz) in float. The
 * tests sit inside the search: a rejected point does not shrink the bound, so the search goes on
 * until the nearest acceptable point is found. A far subtree is skipped only when its splitting plane's d² is
 * strictly above the bound (maxRadius2 until a point is taken, then the best d²). d² is
 * ((px−qx)² + (py−qy)²) + (pz−qz)² without contraction, as in knn.cl. A reached bucket is
 * tested whole with float8 arithmetic (the same d², cover and normal tests on all 8 slots, then
 * the accepted slots in order): a superset of what the node-by-node descent tests, so the same
 * point wins. The upper nodes a descent passes are tested after the bucket it reaches (deepest
 * first), when the bound is tight: the winner does not depend on the order of the tests. */
#pragma OPENCL FP_CONTRACT OFF
#include "shared/types.h"
#include "shared/sampling.h"
#include "shared/kd_buckets.h"

#define PCL_IRRADIANCE_STACK 48

__kernel void precomputed_irradiance_select(__global const PclPhoton* photons, uint n, uint every, float maxRadius2,
                                            uint k, __global PclIrradiancePoint* points,
                                            __global PclEstimateQuery* queries) {
    const uint j = (uint)get_global_id(0);
    const uint count = n == 0u ? 0u : (n - 1u) / every + 1u;
    if (j >= count) return;
    const uint i = j * every;
    const PclPhoton p = photons[i];
    PclIrradiancePoint s;
    s.x = p.x, s.y = p.y, s.z = p.z;
    s.normal = p.normal;
    s.r = s.g = s.b = 0.0f;
    s.photon = i;
    points[j] = s;
    const PclV3 nrm = photon_normal_decode(p.normal);
    PclEstimateQuery q;
    q.x = p.x, q.y = p.y, q.z = p.z;
    q.maxRadius2 = maxRadius2;
    q.nx = nrm.x, q.ny = nrm.y, q.nz = nrm.z;
    q.k = k;
    queries[j] = q;
}

/* The selected photons are left out of the estimates: a stored value then does not depend on
 * where the other stored points lie, so the nearest-point lookup (which picks points with large
 * Voronoi cells more often) is not biased towards sparse, dim neighbourhoods. The others carry
 * (m − 1)/m of the flux: scale brings the estimate back to the whole map's. */
__kernel void precomputed_irradiance_unselected(__global const PclPhoton* photons, uint n, uint every,
                                                __global PclPhoton* others) {
    const uint i = (uint)get_global_id(0);
    if (i >= n || i % every == 0u) return;
    others[i - i / every - 1u] = photons[i];
}

__kernel void precomputed_irradiance_store(__global const PclEstimate* estimates, __global const uint* order,
                                           float scale, float coverScale2, uint count,
                                           __global PclIrradiancePoint* points, __global float* cover,
                                           __global float4* nondirect) {
    const uint s = (uint)get_global_id(0);
    if (s >= count) return;
    const uint j = order[s];
    const PclEstimate e = estimates[s];
    points[j].r = e.r * scale;
    points[j].g = e.g * scale;
    points[j].b = e.b * scale;
    cover[j] = isinf(coverScale2) ? INFINITY : coverScale2 * e.radius2;
    float nr, ng, nb;
    photon_rgbe_decode(e.nondirect, &nr, &ng, &nb);
    nondirect[j] = (float4)(nr * scale, ng * scale, nb * scale, 0.0f);
}

__kernel void precomputed_irradiance_as_photons(__global const PclIrradiancePoint* points, uint n,
                                                __global PclPhoton* photons) {
    const uint i = (uint)get_global_id(0);
    if (i >= n) return;
    const PclIrradiancePoint s = points[i];
    PclPhoton p;
    p.x = s.x, p.y = s.y, p.z = s.z;
    p.rgbe = 0u;
    p.packed = 0u;
    p.normal = s.normal;
    photons[i] = p;
}

__kernel void precomputed_irradiance_pack(__global const PclPhoton* treePhotons, __global const uint* treeIndex,
                                          __global const PclIrradiancePoint* points, __global const float* cover,
                                          __global const float4* nondirect, uint n, __global PclIrradiancePoint* nodes,
                                          __global float* nodeCover, __global float4* nodeNondirect) {
    const uint h = (uint)get_global_id(0);
    if (h >= n) return;
    const uint axis = (treePhotons[h].packed & PCL_PHOTON_AXIS_MASK) >> PCL_PHOTON_AXIS_SHIFT;
    const uint i = treeIndex[h];
    PclIrradiancePoint s = points[i];
    s.photon = (s.photon & PCL_IRRADIANCE_INDEX_MASK) | (axis << PCL_IRRADIANCE_AXIS_SHIFT);
    nodes[h] = s;
    nodeCover[h] = cover[i];
    nodeNondirect[h] = nondirect[i];
}

inline float irradiance_dist2(float px, float py, float pz, float qx, float qy, float qz) {
    const float dx = px - qx, dy = py - qy, dz = pz - qz;
    return dx * dx + dy * dy + dz * dz;
}

/* One work-item per node on the bucket levels (h = bucketFirst + i). */
__kernel void precomputed_irradiance_buckets(__global const PclIrradiancePoint* nodes,
                                             __global const float* nodeCover, uint n, uint bucketFirst,
                                             __global float* buckets) {
    const uint h = bucketFirst + (uint)get_global_id(0);
    if (h >= n) return;
    const PclIrradiancePoint p = nodes[h];
    const PclV3 np = photon_normal_decode(p.normal);
    uint b, s;
    kd_bucket_slot(h, bucketFirst, &b, &s);
    const uint count = kd_bucket_count(n, bucketFirst, b);
    __global float* row = buckets + (size_t)PCL_IRRADIANCE_BUCKET_ROWS * kd_bucket_offset(n, bucketFirst, b) + s;
    const float v[PCL_IRRADIANCE_BUCKET_ROWS] = {p.x, p.y, p.z, nodeCover[h], np.x, np.y, np.z,
                                                 as_float(p.photon & PCL_IRRADIANCE_INDEX_MASK), as_float(h)};
    for (uint r = 0u; r < PCL_IRRADIANCE_BUCKET_ROWS; ++r) row[r * count] = v[r];
}

__kernel void precomputed_irradiance_lookup(__global const PclIrradiancePoint* nodes, __global const float* nodeCover,
                                            __global const float4* nodeNondirect, uint n, uint bucketFirst, __global const float* buckets,
                                            __global const PclEstimateQuery* queries, uint queryCount,
                                            float minNormalCos, uint zeroRadiusIsNone,
                                            __global float4* irradiance, __global uint* chosen) {
    const uint qi = (uint)get_global_id(0);
    if (qi >= queryCount) return;
    const PclEstimateQuery q = queries[qi];
    float bestD2 = q.maxRadius2;
    uint best = PCL_NO_HIT;      /* node */
    uint bestPhoton = PCL_NO_HIT;
    uint stackNode[PCL_IRRADIANCE_STACK];
    float stackD[PCL_IRRADIANCE_STACK];
    uint sp = 0u;
    uint pathNode[PCL_IRRADIANCE_STACK];
    uint pathLength = 0u;
    const bool search = zeroRadiusIsNone ? q.maxRadius2 > 0.0f : q.maxRadius2 >= 0.0f;
    uint node = (n > 0u && search) ? 0u : n;
    for (;;) {
        while (node < n) {
            if (node >= bucketFirst) {
                const uint b = node - bucketFirst, m = kd_bucket_count(n, bucketFirst, b);
                __global const float* row =
                    buckets + (size_t)PCL_IRRADIANCE_BUCKET_ROWS * kd_bucket_offset(n, bucketFirst, b);
                const float8 dx = vload8(0, row) - (float8)(q.x), dy = vload8(0, row + m) - (float8)(q.y),
                             dz = vload8(0, row + 2u * m) - (float8)(q.z);
                const float8 d = (dx * dx + dy * dy) + dz * dz;
                const float8 c = (vload8(0, row + 4u * m) * (float8)(q.nx) + vload8(0, row + 5u * m) * (float8)(q.ny)) +
                                 vload8(0, row + 6u * m) * (float8)(q.nz);
                const int8 lanes = (int8)(0, 1, 2, 3, 4, 5, 6, 7);
                const int8 ok = (lanes < (int8)((int)m)) & (d <= (float8)(bestD2)) & (d <= vload8(0, row + 3u * m)) &
                                (c >= (float8)(minNormalCos));
                if (any(ok)) {
                    const float dd[8] = {d.s0, d.s1, d.s2, d.s3, d.s4, d.s5, d.s6, d.s7};
                    const int oo[8] = {ok.s0, ok.s1, ok.s2, ok.s3, ok.s4, ok.s5, ok.s6, ok.s7};
                    /* the photon index row (ties) and the heap node row (the winner's irradiance) */
                    __global const uint* photons = (__global const uint*)(row + 7u * m);
                    for (uint s = 0u; s < m; ++s) {
                        if (!oo[s] || dd[s] > bestD2) continue;
                        const uint photon = photons[s];
                        if (dd[s] < bestD2 || photon < bestPhoton) {
                            bestD2 = dd[s];
                            best = photons[m + s];
                            bestPhoton = photon;
                        }
                    }
                }
                break;
            }
            const __global PclIrradiancePoint* p = nodes + node;
            const uint axis = p->photon >> PCL_IRRADIANCE_AXIS_SHIFT;
            const float diff = axis == 0u ? q.x - p->x : (axis == 1u ? q.y - p->y : q.z - p->z);
            const uint left = 2u * node + 1u;
            const uint nearChild = diff < 0.0f ? left : left + 1u;
            const uint farChild = diff < 0.0f ? left + 1u : left;
            const float planeD2 = diff * diff;
            if (farChild < n && planeD2 <= bestD2) {
                stackNode[sp] = farChild;
                stackD[sp] = planeD2;
                ++sp;
            }
            pathNode[pathLength++] = node;
            node = nearChild;
        }
        /* The descent's own points, deepest first: tested after the bucket below them, most
         * fail on d² against its bound before their cover and normal are read. */
        while (pathLength > 0u) {
            const uint h = pathNode[--pathLength];
            const __global PclIrradiancePoint* p = nodes + h;
            const float d = irradiance_dist2(p->x, p->y, p->z, q.x, q.y, q.z);
            const uint photon = p->photon & PCL_IRRADIANCE_INDEX_MASK;
            if ((d < bestD2 || (d == bestD2 && photon < bestPhoton)) && d <= nodeCover[h]) {
                const PclV3 np = photon_normal_decode(p->normal);
                const float c = (np.x * q.nx + np.y * q.ny) + np.z * q.nz;
                if (c >= minNormalCos) {
                    bestD2 = d;
                    best = h;
                    bestPhoton = photon;
                }
            }
        }
        node = n;
        while (sp > 0u) {
            --sp;
            if (stackD[sp] <= bestD2) {
                node = stackNode[sp];
                break;
            }
        }
        if (node >= n) break;
    }
    if (best == PCL_NO_HIT) {
        irradiance[qi] = (float4)(0.0f, 0.0f, 0.0f, 0.0f);
        chosen[qi] = PCL_NO_HIT;
    } else {
        const PclIrradiancePoint p = nodes[best];
        if (q.k & PCL_QUERY_NONDIRECT) {
            const float4 e = nodeNondirect[best];
            irradiance[qi] = (float4)(e.x, e.y, e.z, bestD2);
        } else {
            irradiance[qi] = (float4)(p.r, p.g, p.b, bestD2);
        }
        chosen[qi] = bestPhoton;
    }
}
