/* direct_light.cl: direct light at the diffuse eye hits by shadow rays (kernels/README.md,
 * "Eye pass: direct light"); one eye record per work-item.
 *
 * in:  params                  PclDirectParams: pass seed, n², sampleCount, lightCount,
 *                              triangleCount, M light samples, N gather rays (for MIS),
 *                              areaPowerTotal, rayEpsilon
 *      hits[i]                 PclEyeHit (eye_paths)
 *      nodes, packets, spheres the BVH; primInfo, materials, lights[]
 *      areaCdf[l]              the triangle lights' cumulative choice probability (host table)
 * out: radiance[i]             PclRadiance: throughput × ρd/π × Σ (0 without a diffuse hit)
 *
 * Point, spot, directional lights: every one, one exact shadow ray each. Triangle lights: M
 * samples m; random numbers stream LIGHT, path = pixel, bounce = k·M + m, block 0: u0 chooses
 * the light (the first l with u0 < areaCdf[l]), (u1, u2) the point. */
#include "shared/types.h"
#include "shared/rng.h"
#include "shared/sampling.h"
#include "shared/bvh.h"
#include "shared/eye.h"

#pragma OPENCL FP_CONTRACT OFF

/* Unoccluded segment from o (already lifted) to o + dir·t, t in (0, tmax). */
inline bool direct_visible(__global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                           __global const PclSphere* spheres, PclV3 o, PclV3 dir, float tmax, float tau) {
    const PclRay r = bvh_ray(o.x, o.y, o.z, dir.x, dir.y, dir.z, 0.0f, tmax, tau);
    PclHit hit;
    return !bvh_trace(nodes, packets, spheres, r, true, &hit);
}

inline float direct_smoothstep(float e0, float e1, float x) {
    if (e1 <= e0) return x >= e1 ? 1.0f : 0.0f;
    float t = (x - e0) / (e1 - e0);
    t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
    return t * t * (3.0f - 2.0f * t);
}

__kernel void direct_light(const PclDirectParams params, __global const PclEyeHit* hits,
                           __global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                           __global const PclSphere* spheres, __global const PclPrimInfo* primInfo,
                           __global const PclMaterial* materials, __global const PclLight* lights,
                           __global const float* areaCdf, __global const float* histograms,
                           __global PclRadiance* radiance) {
    const uint i = (uint)get_global_id(0);
    if (i >= params.sampleCount) return;
    const PclEyeHit h = hits[i];
    PclRadiance out;
    out.r = out.g = out.b = out.a = 0.0f;
    if (!(h.flags & PCL_EYE_DIFFUSE)) {
        radiance[i] = out;
        return;
    }
    const ulong seed = (ulong)params.seedLo | ((ulong)params.seedHi << 32);
    const PclV3 p = sampling_v3(h.x, h.y, h.z);
    const PclV3 nf = sampling_v3(h.nx, h.ny, h.nz);
    const float tau = h.time;
    const float eps = params.rayEpsilon;
    const PclV3 o = eye_add_scaled(p, nf, eps);
    float sum[3] = {0.0f, 0.0f, 0.0f};

    /* Delta lights: exact. */
    for (uint l = 0u; l < params.lightCount; ++l) {
        const PclLight L = lights[l];
        if (L.type == PCL_LIGHT_TRIANGLE) continue;
        if (L.type == PCL_LIGHT_DIRECTIONAL) {
            const PclV3 wi = sampling_v3(-L.axis[0], -L.axis[1], -L.axis[2]);
            const float cosS = sampling_dot(nf, wi);
            if (!(cosS > 0.0f)) continue;
            if (!direct_visible(nodes, packets, spheres, o, wi, INFINITY, tau)) continue;
            const float scale = cosS / (PCL_PI_F * L.radius * L.radius);  /* E = Φ / (π R²) */
            for (int c = 0; c < 3; ++c) sum[c] = sum[c] + L.power[c] * scale;
            continue;
        }
        const PclV3 toL = sampling_v3(L.p[0] - p.x, L.p[1] - p.y, L.p[2] - p.z);
        const float d2 = sampling_dot(toL, toL);
        if (!(d2 > 0.0f)) continue;
        const float dist = sqrt(d2);
        const PclV3 wi = sampling_v3(toL.x / dist, toL.y / dist, toL.z / dist);
        const float cosS = sampling_dot(nf, wi);
        if (!(cosS > 0.0f)) continue;
        float scale;  /* I / Φ × falloff */
        if (L.type == PCL_LIGHT_POINT) {
            scale = 1.0f / (4.0f * PCL_PI_F);
        } else {
            const float cosAxis = -(L.axis[0] * wi.x + L.axis[1] * wi.y + L.axis[2] * wi.z);
            const float falloff = direct_smoothstep(L.cosOuter, L.cosInner, cosAxis);
            if (!(falloff > 0.0f)) continue;
            scale = falloff / (2.0f * PCL_PI_F * ((1.0f - L.cosInner) + 0.5f * (L.cosInner - L.cosOuter)));
        }
        const PclV3 seg = sampling_v3(L.p[0] - o.x, L.p[1] - o.y, L.p[2] - o.z);
        if (!direct_visible(nodes, packets, spheres, o, seg, 1.0f, tau)) continue;
        const float f = scale * cosS / d2;
        for (int c = 0; c < 3; ++c) sum[c] = sum[c] + L.power[c] * f;
    }

    /* Triangle lights: M samples by area, MIS (power heuristic) against N cosine samples. */
    const uint M = params.lightSamples;
    if (params.areaPowerTotal > 0.0f && M > 0u) {
        float area[3] = {0.0f, 0.0f, 0.0f};
        for (uint m = 0u; m < M; ++m) {
            uint w[4];
            rng_block(seed, h.pixel, h.sample * M + m, 0u, PCL_RNG_STREAM_LIGHT, w);
            const float u0 = rng_u01(w[0]);
            uint l = 0u;
            while (l + 1u < params.lightCount && !(u0 < areaCdf[l])) ++l;
            const PclLight L = lights[l];
            if (L.type != PCL_LIGHT_TRIANGLE) continue;
            float b0, b1;
            sampling_uniform_triangle(rng_u01(w[1]), rng_u01(w[2]), &b0, &b1);
            const float b2 = 1.0f - b0 - b1;
            const PclV3 q = sampling_v3(L.p[0] + L.e1[0] * b1 + L.e2[0] * b2 + L.motion[0] * tau,
                                        L.p[1] + L.e1[1] * b1 + L.e2[1] * b2 + L.motion[1] * tau,
                                        L.p[2] + L.e1[2] * b1 + L.e2[2] * b2 + L.motion[2] * tau);
            const PclV3 toL = sampling_v3(q.x - p.x, q.y - p.y, q.z - p.z);
            const float d2 = sampling_dot(toL, toL);
            if (!(d2 > 0.0f)) continue;
            const float dist = sqrt(d2);
            const PclV3 wi = sampling_v3(toL.x / dist, toL.y / dist, toL.z / dist);
            const float cosS = sampling_dot(nf, wi);
            if (!(cosS > 0.0f)) continue;
            const float pdfL = eye_area_light_pdf(L, params.areaPowerTotal, wi, d2);
            if (!(pdfL > 0.0f)) continue;
            const PclV3 end = sampling_v3(q.x + L.axis[0] * eps, q.y + L.axis[1] * eps, q.z + L.axis[2] * eps);
            const PclV3 seg = sampling_v3(end.x - o.x, end.y - o.y, end.z - o.z);
            if (!direct_visible(nodes, packets, spheres, o, seg, 1.0f, tau)) continue;
            float pdfB = cosS / PCL_PI_F;
            if (params.histogramCells > 0u) {  /* the gather rays' importance density */
                const uint G = params.histogramCells;
                __global const float* cdf = histograms + (size_t)i * G * G;
                pdfB = pdfB * ((float)(G * G) * eye_cell_probability(cdf, eye_cell_of_direction(nf, wi, G)));
            }
            const float wMis = params.gatherRays == 0u ? 1.0f : eye_mis_weight(M, pdfL, params.gatherRays, pdfB);
            const float f = cosS * wMis / pdfL;
            const PclMaterial E = materials[primInfo[L.prim].material];
            for (int c = 0; c < 3; ++c) area[c] = area[c] + E.emission[c] * f;
        }
        for (int c = 0; c < 3; ++c) sum[c] = sum[c] + area[c] / (float)M;
    }
    float L3[3];
    for (int c = 0; c < 3; ++c) {
        L3[c] = h.throughput[c] * (h.albedo[c] / PCL_PI_F) * sum[c];
        if (!isfinite(L3[c])) L3[c] = 0.0f;
    }
    out.r = L3[0];
    out.g = L3[1];
    out.b = L3[2];
    radiance[i] = out;
}
