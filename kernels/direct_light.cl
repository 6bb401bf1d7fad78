/* direct_light.cl: direct light at the diffuse eye hits by shadow rays (kernels/README.md,
 * "Eye pass: direct light"); one eye record per work-item.
 *
 * in:  params                  PclDirectParams: pass seed, n², sampleCount, lightCount,
 *                              triangleCount, M light samples, N gather rays (for MIS),
 *                              areaPowerTotal, rayEpsilon
 *      hits[i]                 PclEyeHit (eye_paths)
 *      nodes, packets, spheres the BVH; primInfo, materials, lights[]
 *      areaCdf[l]              the triangle lights' cumulative choice probability (host table)
 *      histograms              the gather's importance tables (histogramCells > 0)
 *      media[], primMedia[prim] participating media (read only when params.hasMedia): every
 *                              shadow ray carries the transmittance of the media and invisible
 *                              boundaries it crosses (shared/eye_medium.h), starting in the
 *                              medium on the record's side of its surface (primMedia: outside
 *                              when n_f is the outside normal)
 *      env, envData[]          the sky (shared/environment.h)
 *      materialTextures, texels, triangleUvs
 *                              emission textures: a triangle light's radiance at the point
 *                              sampled (read only with PCL_TEXTURED, shared/texture.h)
 *      strata[2s], [2s + 1]    the cell of sample s of the pass's pattern of n²M for the triangle
 *                              lights' points; strata[2n²M + 2s], [… + 1] for the sky's
 *                              directions (stratify.h, stratify_cmj_cell; words 0 and 1 of
 *                              (PCL_PASS_PATTERN_PATH, PCL_LIGHT_PATTERN_BOUNCE, block 0))
 * out: radiance[i]             PclRadiance: throughput × ρd/π × Σ (0 without a diffuse hit)
 *
 * Point, spot, directional lights: every one, one exact shadow ray each. Triangle lights: M
 * samples m; random numbers stream LIGHT, path = pixel, bounce = k·M + m, block 0: u0 chooses
 * the light (the first l with u0 < areaCdf[l]), (u1, u2) jitter the point's cell, sample k·M + m
 * of the pass's pattern, shifted for the pixel by words 0 and 1 of (pixel,
 * PCL_LIGHT_PATTERN_BOUNCE, block 0) (stratify_shifted).
 *
 * The sky: M more samples m by its map (shared/environment.h), block 1 of the same counters:
 * (u0, u1) jitter the direction's cell, stratified as the triangle lights' points (the second
 * pattern, shifted by words 2 and 3); MIS (power heuristic) against the N gather rays as for triangle lights (final_gather
 * adds the sky a gather ray escapes to with the other half). */
#include "shared/types.h"
#include "shared/rng.h"
#include "shared/stratify.h"
#include "shared/sampling.h"
#include "shared/bvh.h"
#include "shared/eye.h"
#include "shared/eye_medium.h"
#include "shared/light_sample.h"
#include "shared/environment.h"

#pragma OPENCL FP_CONTRACT OFF

#include "shared/texture.h"

__kernel void direct_light(const PclDirectParams params, __global const PclEyeHit* hits,
                           __global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                           __global const PclSphere* spheres, __global const PclPrimInfo* primInfo,
                           __global const PclMaterial* materials, __global const PclLight* lights,
                           __global const float* areaCdf, __global const float* histograms,
                           __global const PclMedium* media, __global const PclPrimMedium* primMedia,
                           __global PclRadiance* radiance, const PclEnvironment env, __global const float* envData,
                           __global const PclMaterialTextures* materialTextures, __global const float* texels,
                           __global const PclTriangleUv* triangleUvs, __global const uint* strata) {
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
    const PclV3 sf = sampling_v3(h.snx, h.sny, h.snz); /* the shading normal: cosines and the gather frame */
    const float tau = h.time;
    const float eps = params.rayEpsilon;
    const PclV3 o = eye_add_scaled(p, nf, eps);
    float sum[3] = {0.0f, 0.0f, 0.0f};
    const EyeMedia em =
        eye_media(primInfo, materials, media, primMedia, params.triangleCount, params.hasMedia, eps);
    const LightTextures lt = light_textures(materialTextures, texels, triangleUvs, params.triangleCount);
    int medium = PCL_NO_MEDIUM;
    if (params.hasMedia) {
        const PclV3 n = eye_normal(primInfo, h.prim, params.triangleCount, p, tau);
        medium = sampling_dot(nf, n) > 0.0f ? primMedia[h.prim].outside : primMedia[h.prim].inside;
    }

    /* Delta lights: exact. */
    light_delta_irradiance(nodes, packets, spheres, em, medium, lights, params.lightCount, p, nf, sf, o, tau, sum);

    /* Triangle lights: M samples by area, MIS (power heuristic) against N cosine samples. The
     * pixel's n² M points of this pass are stratified together (shared/stratify.h), as are its
     * sky directions: the pass's patterns, shifted by the words of (pixel, PCL_LIGHT_PATTERN_BOUNCE,
     * block 0). */
    const uint M = params.lightSamples;
    const uint count = params.samplesPerPixel * M, cells = stratify_cells(count);
    uint shift[4] = {0u, 0u, 0u, 0u};
    if (M > 0u && (params.areaPowerTotal > 0.0f || env_active(env))) /* none for delta lights alone */
        rng_block(seed, h.pixel, PCL_LIGHT_PATTERN_BOUNCE, 0u, PCL_RNG_STREAM_LIGHT, shift);
    if (params.areaPowerTotal > 0.0f && M > 0u) {
        float area[3] = {0.0f, 0.0f, 0.0f};
        for (uint m = 0u; m < M; ++m) {
            uint w[4];
            rng_block(seed, h.pixel, h.sample * M + m, 0u, PCL_RNG_STREAM_LIGHT, w);
            float u1, u2;
            const uint s = h.sample * M + m;
            stratify_shifted(strata[2u * s], strata[2u * s + 1u], cells, count, rng_u01(w[1]), rng_u01(w[2]),
                             rng_u01(shift[0]), rng_u01(shift[1]), &u1, &u2);
            PclV3 wi;
            float pdfL, cosS, le[3];
            if (!light_area_sample(nodes, packets, spheres, em, medium, primInfo, materials, lt, lights, areaCdf, params.lightCount,
                                   params.areaPowerTotal, p, nf, sf, o, eps, tau, rng_u01(w[0]), u1, u2, &wi, &pdfL,
                                   &cosS, le))
                continue;
            float pdfB = cosS / PCL_PI_F;
            if (params.histogramCells > 0u) {  /* the gather rays' importance density */
                const uint G = params.histogramCells;
                __global const float* cdf = histograms + (size_t)i * G * G;
                pdfB = pdfB * ((float)(G * G) * eye_cell_probability(cdf, eye_cell_of_direction(sf, wi, G)));
            }
            const float wMis = params.gatherRays == 0u ? 1.0f : eye_mis_weight(M, pdfL, params.gatherRays, pdfB);
            const float f = cosS * wMis / pdfL;
            for (int c = 0; c < 3; ++c) area[c] = area[c] + le[c] * f;
        }
        for (int c = 0; c < 3; ++c) sum[c] = sum[c] + area[c] / (float)M;
    }

    /* The sky: M samples by its map, MIS against N gather rays. */
    if (env_active(env) && M > 0u) {
        float sky[3] = {0.0f, 0.0f, 0.0f};
        for (uint m = 0u; m < M; ++m) {
            uint w[4];
            rng_block(seed, h.pixel, h.sample * M + m, 1u, PCL_RNG_STREAM_LIGHT, w);
            float u0, u1;
            const uint s = count + h.sample * M + m;
            stratify_shifted(strata[2u * s], strata[2u * s + 1u], cells, count, rng_u01(w[0]), rng_u01(w[1]),
                             rng_u01(shift[2]), rng_u01(shift[3]), &u0, &u1);
            PclV3 wi;
            float pdfL, cosS, le[3];
            if (!light_sky_sample(nodes, packets, spheres, em, medium, env, envData, nf, sf, o, tau, u0, u1, &wi, &pdfL,
                                  &cosS, le))
                continue;
            float pdfB = cosS / PCL_PI_F;
            if (params.histogramCells > 0u) {
                const uint G = params.histogramCells;
                __global const float* cdf = histograms + (size_t)i * G * G;
                pdfB = pdfB * ((float)(G * G) * eye_cell_probability(cdf, eye_cell_of_direction(sf, wi, G)));
            }
            const float wMis = params.gatherRays == 0u ? 1.0f : eye_mis_weight(M, pdfL, params.gatherRays, pdfB);
            const float f = cosS * wMis / pdfL;
            for (int c = 0; c < 3; ++c) sky[c] = sky[c] + le[c] * f;
        }
        for (int c = 0; c < 3; ++c) sum[c] = sum[c] + sky[c] / (float)M;
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
