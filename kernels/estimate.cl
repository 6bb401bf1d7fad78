/* estimate.cl: the irradiance estimate at each query from its k nearest photons (kernels/
 * README.md, "estimate"; Jensen 2001 §7.2), one query per work-item, after the kNN search
 * (knn.cl) of the same batch.
 *
 * estimate_knn_queries
 *   in:  params (firstQuery, queryCount, stride), maxSearchRadius2 (the hash grid's r_max², else
 *        +inf), queries[firstQuery + i] PclEstimateQuery
 *   out: knnQueries[i] PclKnnQuery = (x, y, z, min(maxRadius2, maxSearchRadius2), min(k, stride)),
 *        i < queryCount
 * estimate_irradiance
 *   in:  params                      PclEstimateParams (filter, coneK, norm, gaussianScale,
 *                                    minNormalCos, visibility, rayEpsilon, liftFraction, batch)
 *        queries[firstQuery + i]     position, unit normal n_q of the shaded side
 *        photons[]                   the map in map order (kNN indices refer to it)
 *        counts[i], indices[i·stride + j], dist2[i·stride + j], radius2[i]   the kNN's output
 *        nodes, packets, spheres     the scene BVH (shared/bvh.h), read only with visibility
 *        dirTable[1024]              cos θ, sin θ, cos φ, sin φ per direction byte (host-made)
 *   out: results[firstQuery + i]     PclEstimate: E rgb = Σ w(u²) ΔΦ_p / ((norm·π)·r²) over the
 *                                    neighbours that pass the tests, in kNN order; r² = radius2;
 *                                    used; found = counts[i]. r² = 0 gives exactly 0.
 *                                    r² is the kNN's radius2, or min(query maxRadius2,
 *                                    maxSearchRadius2) when 0 < found < k and that is finite.
 *                                    nondirect: RGBE of the same sum over the photons of bounce
 *                                    > 0 alone; a query with PCL_QUERY_NONDIRECT in k gets that
 *                                    sum (in float) as its E.
 *
 * Tests per neighbour (in this order): w_p·n_q > 0 (incoming direction on the shaded side),
 * n_p·n_q ≥ minNormalCos, and with visibility no hit in (0, 1) along the segment from
 * x + h n_q to p + h n_p, h = rayEpsilon + liftFraction·r (closest-hit traversal, time 0).
 * Dot products are (a.x b.x + a.y b.y) + a.z b.z; FP_CONTRACT is off so the twin repeats the
 * arithmetic (up to exp, and division and sqrt where not correctly rounded: see the README).
 * options: -DPCL_BVH_STACK_SIZE=n (DeviceGeometry::programOptions) */
#pragma OPENCL FP_CONTRACT OFF
#include "shared/types.h"
#include "shared/sampling.h"
#include "shared/bvh.h"

__kernel void estimate_knn_queries(const PclEstimateParams params, const float maxSearchRadius2,
                                   __global const PclEstimateQuery* queries, __global PclKnnQuery* knnQueries) {
    const uint i = (uint)get_global_id(0);
    if (i >= params.queryCount) return;
    const PclEstimateQuery q = queries[params.firstQuery + i];
    PclKnnQuery k;
    k.x = q.x;
    k.y = q.y;
    k.z = q.z;
    k.maxRadius2 = min(q.maxRadius2, maxSearchRadius2);
    k.k = min(q.k & PCL_QUERY_K_MASK, params.stride);
    k.pad0 = k.pad1 = k.pad2 = 0u;
    knnQueries[i] = k;
}

/* w at u² = d²/r² (u² ≤ 1). */
inline float estimate_weight(const PclEstimateParams* p, float u2) {
    switch (p->filter) {
        case PCL_FILTER_CONE: return 1.0f - sqrt(u2) / p->coneK;
        case PCL_FILTER_EPANECHNIKOV: return 1.0f - u2;
        case PCL_FILTER_GAUSSIAN: return 1.0f - (1.0f - exp(u2 * (-0.5f * PCL_GAUSSIAN_BETA))) * p->gaussianScale;
        default: return 1.0f;
    }
}

inline float estimate_dot(PclV3 a, float bx, float by, float bz) { return a.x * bx + a.y * by + a.z * bz; }

/* The incoming direction of a photon record from the host's table (Jensen's lookup tables,
 * §5.4): dirTable[b] = cos θ_b, [256 + b] = sin θ_b, [512 + b] = cos φ_b, [768 + b] = sin φ_b
 * at the byte cells' centres, so no sin or cos runs per photon and the twin gets the same bits. */
inline PclV3 estimate_dir(__constant const float* dirTable, uint packed) {
    const uint t = packed & 255u, p = (packed >> 8) & 255u;
    const float st = dirTable[256u + t];
    return sampling_v3(st * dirTable[512u + p], st * dirTable[768u + p], dirTable[t]);
}

__kernel void estimate_irradiance(const PclEstimateParams params, __global const PclEstimateQuery* queries,
                                  __global const PclPhoton* photons, __global const uint* counts,
                                  __global const uint* indices, __global const float* dist2,
                                  __global const float* radius2, __global const PclBvhNode* nodes,
                                  __global const PclTriPacket* packets, __global const PclSphere* spheres,
                                  __constant const float* dirTable, __global PclEstimate* results) {
    const uint i = (uint)get_global_id(0);
    if (i >= params.queryCount) return;
    const PclEstimateQuery q = queries[params.firstQuery + i];
    const uint found = counts[i];
    /* Fewer than k found: the search saw every photon within its radius, so the disc is that
     * radius's, not the farthest photon's (dividing by the farthest photon's r² reads high by
     * about 1/found: +6 % in a furnace of 1 000 photons, where r_max capped the search). */
    const float cap2 = min(q.maxRadius2, params.maxSearchRadius2);
    const float r2 = (found > 0u && found < min(q.k & PCL_QUERY_K_MASK, params.stride) && isfinite(cap2)) ? cap2 : radius2[i];
    float sr = 0.0f, sg = 0.0f, sb = 0.0f;
    float nr = 0.0f, ng = 0.0f, nb = 0.0f; /* the photons of bounce > 0 alone */
    uint used = 0u;
    if (r2 > 0.0f) {
        const float h = params.rayEpsilon + params.liftFraction * sqrt(r2);
        const float ax = q.x + h * q.nx, ay = q.y + h * q.ny, az = q.z + h * q.nz;
        const size_t base = (size_t)i * params.stride;
        for (uint j = 0u; j < found; ++j) {
            const PclPhoton p = photons[indices[base + j]];
            const PclV3 w = estimate_dir(dirTable, p.packed);
            if (!(estimate_dot(w, q.nx, q.ny, q.nz) > 0.0f)) continue;
            const PclV3 n = photon_normal_decode(p.normal);
            if (!(estimate_dot(n, q.nx, q.ny, q.nz) >= params.minNormalCos)) continue;
            if (params.visibility) {
                const PclRay ray = bvh_ray(ax, ay, az, (p.x + h * n.x) - ax, (p.y + h * n.y) - ay,
                                           (p.z + h * n.z) - az, 0.0f, 1.0f, 0.0f);
                PclHit hit;
                if (bvh_trace(nodes, packets, spheres, ray, false, &hit)) continue;
            }
            const float wt = estimate_weight(&params, dist2[base + j] / r2);
            float pr, pg, pb;
            photon_rgbe_decode(p.rgbe, &pr, &pg, &pb);
            sr += wt * pr;
            sg += wt * pg;
            sb += wt * pb;
            if (((p.packed >> PCL_PHOTON_BOUNCE_SHIFT) & 255u) != 0u) {
                nr += wt * pr;
                ng += wt * pg;
                nb += wt * pb;
            }
            ++used;
        }
    }
    PclEstimate e;
    e.nondirect = 0u;
    if (used > 0u) {
        const float denom = (params.norm * PCL_PI_F) * r2;
        const bool nondirect = (q.k & PCL_QUERY_NONDIRECT) != 0u;
        e.r = (nondirect ? nr : sr) / denom;
        e.g = (nondirect ? ng : sg) / denom;
        e.b = (nondirect ? nb : sb) / denom;
        e.nondirect = photon_rgbe_encode(nr / denom, ng / denom, nb / denom);
    } else {
        e.r = e.g = e.b = 0.0f;
    }
    e.radius2 = r2;
    e.used = used;
    e.found = found;
    e.pad0 = 0u;
    results[params.firstQuery + i] = e;
}
