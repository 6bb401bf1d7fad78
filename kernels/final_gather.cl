/* final_gather.cl: final gathering at the diffuse eye hits (kernels/README.md, "Eye pass:
 * final gather").
 *
 * final_gather_trace — one gather ray per work-item j = i·N + g (record i, ray g):
 * in:  params                  PclGatherParams: pass seed, n², sampleCount, N, scene counts,
 *                              maxSpecular, M (for MIS), k and maxRadius2 for the queries,
 *                              areaPowerTotal, rayEpsilon
 *      hits[i]                 PclEyeHit (eye_paths)
 *      nodes, packets, spheres the BVH; primInfo, materials, lights[]
 *      lightOfPrim[prim]       light index of an emitting triangle, PCL_NO_HIT otherwise
 *      areaCdf[l]              the triangle lights' cumulative choice probability (direct_light's)
 * out: queries[j]              PclEstimateQuery at the gather hit (viewer-side normal, k,
 *                              maxRadius2), or maxRadius2 = 0 at the origin when there is none;
 *                              a hit whose path from the eye hit (through mirrors and glass too)
 *                              is shorter than params.closeDistance
 *                              asks PCL_QUERY_NONDIRECT and adds its direct light to emitted
 *                              (gather_direct: weight × E_direct)
 *      gathered[j]             PclGatherHit: weight (chain throughput × ρd/π / P_d) and emitted
 *                              (chain throughput × Le × MIS weight)
 *      env, envData[]          the sky (shared/environment.h): a gather ray that leaves the
 *                              scene straight from the eye hit adds its radiance with the MIS
 *                              weight against direct_light's M sky samples; after a specular
 *                              bounce in full, or not at all when the caustic map is read and
 *                              holds the sky's photons (causticSky)
 *      strata[2s], [2s + 1]     the cell of sample s of the pass's pattern of n²N (stratify.h,
 *                              stratify_cmj_cell; word 0 of (PCL_PASS_PATTERN_PATH,
 *                              PCL_GATHER_PATTERN_BOUNCE, block 0) its pattern)
 * Random numbers: stream GATHER, path = pixel, bounce = k·N + g; block 0: (u0, u1) the jitter of
 * the cosine direction's cell, sample k·N + g of the pass's pattern, shifted for the pixel by words
 * 0 and 1 of (pixel, PCL_GATHER_PATTERN_BOUNCE, block 0) (stratify_shifted; with importance
 * histograms that sample's v picks the cell: see below); block b + 1 at gather
 * hit b: u0 lobe, u1 reflect/refract, (u2, u3) glossy direction (drawn only where the hit has a
 * specular lobe); at a close hit, block PCL_GATHER_DIRECT_BLOCK: u0 the triangle light, (u1, u2)
 * its point, and block PCL_GATHER_DIRECT_BLOCK + 1: (u0, u1) the sky direction (gather_direct).
 *
 * final_gather_resolve — one eye record per work-item:
 * in:  hits, gathered, irradiance (params.irradianceStride floats per query, rgb first)
 * out: radiance[i] = throughput × ρd × (1/N) Σ_g (weight_g E_g + emitted_g) */
#include "shared/types.h"
#include "shared/rng.h"
#include "shared/stratify.h"
#include "shared/sampling.h"
#include "shared/bvh.h"
#include "shared/eye.h"
#include "shared/eye_medium.h"
#include "shared/light_sample.h"
#include "shared/environment.h"
#include "shared/texture.h"
#include "shared/shading_frame.h"
#include "shared/shutter_open.h"

#pragma OPENCL FP_CONTRACT OFF

/* The direct irradiance at a close gather hit p (facing normals nf, sf; o = p lifted): every
 * delta light exactly, one triangle-light sample and one sky sample (blocks PCL_GATHER_DIRECT_BLOCK
 * and + 1), each weighted 1: the map's answer there leaves out the photons straight from a light,
 * and no BSDF-sampled ray leaves p, so nothing else counts this light. */
inline void gather_direct(__global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                          __global const PclSphere* spheres, __global const PclPrimInfo* primInfo,
                          __global const PclMaterial* materials, __global const PclLight* lights,
                          __global const float* areaCdf, const LightTextures lt, const PclEnvironment env,
                          __global const float* envData, const PclGatherParams* params, ulong seed, uint pixel,
                          uint bounceWord, float tau, PclV3 p, PclV3 nf, PclV3 sf, float E[3]) {
    const float eps = params->rayEpsilon;
    const PclV3 o = eye_add_scaled(p, nf, eps);
    const EyeMedia em = eye_media(primInfo, materials, (__global const PclMedium*)0,
                                  (__global const PclPrimMedium*)0, params->triangleCount, 0u, eps);
    for (int c = 0; c < 3; ++c) E[c] = 0.0f;
    light_delta_irradiance(nodes, packets, spheres, em, PCL_NO_MEDIUM, lights, params->lightCount, p, nf, sf, o, tau, E);
    uint w[4];
    if (params->areaPowerTotal > 0.0f) {
        rng_block(seed, pixel, bounceWord, PCL_GATHER_DIRECT_BLOCK, PCL_RNG_STREAM_GATHER, w);
        PclV3 wi;
        float pdfL, cosS, le[3];
        if (light_area_sample(nodes, packets, spheres, em, PCL_NO_MEDIUM, primInfo, materials, lt, lights, areaCdf,
                              params->lightCount, params->areaPowerTotal, p, nf, sf, o, eps, tau, rng_u01(w[0]),
                              rng_u01(w[1]), rng_u01(w[2]), &wi, &pdfL, &cosS, le)) {
            const float f = cosS / pdfL;
            for (int c = 0; c < 3; ++c) E[c] = E[c] + le[c] * f;
        }
    }
    if (env_active(env)) {
        rng_block(seed, pixel, bounceWord, PCL_GATHER_DIRECT_BLOCK + 1u, PCL_RNG_STREAM_GATHER, w);
        PclV3 wi;
        float pdfL, cosS, le[3];
        if (light_sky_sample(nodes, packets, spheres, em, PCL_NO_MEDIUM, env, envData, nf, sf, o, tau, rng_u01(w[0]),
                             rng_u01(w[1]), &wi, &pdfL, &cosS, le)) {
            const float f = cosS / pdfL;
            for (int c = 0; c < 3; ++c) E[c] = E[c] + le[c] * f;
        }
    }
}

__kernel void final_gather_trace(const PclGatherParams params, __global const PclEyeHit* hits,
                                 __global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                                 __global const PclSphere* spheres, __global const PclPrimInfo* primInfo,
                                 __global const PclMaterial* materials, __global const PclLight* lights,
                                 __global const uint* lightOfPrim, __global const float* areaCdf,
                                 __global const float* histograms,
                                 __global PclEstimateQuery* queries, __global PclGatherHit* gathered,
                                 const PclEnvironment env, __global const float* envData,
                                 __global const PclMaterialTextures* materialTextures, __global const float* texels,
                                 __global const PclTriangleUv* triangleUvs,
                                 __global const PclTriangleNormals* triangleNormals,
                                 __global const PclNormalMap* normalMaps,
                                 __global const PclTriangleTangents* triangleTangents,
                                 __global const uint* strata) {
    const uint j = (uint)get_global_id(0);
    const uint N = params.gatherRays;
    if (j >= params.sampleCount * N) return;
    const uint i = j / N, g = j - i * N;
    const PclEyeHit h = hits[i];

    PclEstimateQuery q;
    q.x = q.y = q.z = 0.0f;
    q.maxRadius2 = 0.0f;
    q.nx = 0.0f; q.ny = 0.0f; q.nz = 1.0f;
    q.k = params.k;
    PclGatherHit out;
    for (int c = 0; c < 4; ++c) out.weight[c] = out.emitted[c] = 0.0f;
    if (!(h.flags & PCL_EYE_DIFFUSE)) {
        queries[j] = q;
        gathered[j] = out;
        return;
    }
    const ulong seed = (ulong)params.seedLo | ((ulong)params.seedHi << 32);
    const uint bounceWord = h.sample * N + g;
    const PclV3 p0 = sampling_v3(h.x, h.y, h.z);
    const PclV3 n0 = sampling_v3(h.nx, h.ny, h.nz);
    const PclV3 s0 = sampling_v3(h.snx, h.sny, h.snz); /* the gather rays' frame: the shading normal */
    const float tau = h.time;
    uint w[4];
    rng_block(seed, h.pixel, bounceWord, 0u, PCL_RNG_STREAM_GATHER, w);
    float s1 = rng_u01(w[0]), s2 = rng_u01(w[1]);
    float ratio = 1.0f;  /* cosine density / sampling density */
    const uint G = params.histogramCells;
    /* The pixel's n² N directions of this pass stratified together (shared/stratify.h). */
    uint shift[4];
    rng_block(seed, h.pixel, PCL_GATHER_PATTERN_BOUNCE, 0u, PCL_RNG_STREAM_GATHER, shift);
    const uint count = params.samplesPerPixel * N;
    stratify_shifted(strata[2u * bounceWord], strata[2u * bounceWord + 1u], stratify_cells(count), count, s1, s2,
                     rng_u01(shift[0]), rng_u01(shift[1]), &s1, &s2);
    if (G > 0u) {
        /* A cell by the record's cumulative table at s2, then (s1, s2's place in the cell's span
         * of the table) within it: uniform there, and the cells keep the strata's spread. */
        __global const float* cdf = histograms + (size_t)i * G * G;
        uint c = 0u;
        while (c + 1u < G * G && !(s2 < cdf[c])) ++c;
        const float lo = c == 0u ? 0.0f : cdf[c - 1u], span = cdf[c] - lo;
        float t = span > 0.0f ? (s2 - lo) / span : 0.5f;
        t = t < 0x1.fffffep-1f ? t : 0x1.fffffep-1f;
        s1 = ((float)(c % G) + s1) / (float)G;
        s2 = ((float)(c / G) + t) / (float)G;
        ratio = 1.0f / ((float)(G * G) * eye_cell_probability(cdf, c));
    }
    PclV3 d = sampling_cosine_hemisphere(s0, s1, s2);
    const float pdfB = sampling_dot(s0, d) / PCL_PI_F / ratio;  /* the gather ray's density */
    if (shading_is_smooth(s0, n0) && !(sampling_dot(d, n0) > 0.0f)) {
        /* Below the geometric surface: the BSDF is 0 there (no light through the surface). */
        queries[j] = q;
        gathered[j] = out;
        return;
    }
    PclV3 o = eye_add_scaled(p0, n0, params.rayEpsilon);
    float T[3] = {ratio, ratio, ratio}, Le[3] = {0.0f, 0.0f, 0.0f};
    bool afterSpecular = false;
    float travelled = 0.0f;

    for (uint b = 0u; b <= params.maxSpecular; ++b) {
        const PclRay ray = bvh_ray(o.x, o.y, o.z, d.x, d.y, d.z, 0.0f, INFINITY, tau);
        PclHit hit;
        if (!bvh_trace(nodes, packets, spheres, ray, false, &hit)) {
            if (env_active(env) && !(afterSpecular && params.causticMapRead != 0u && params.causticSky != 0u)) {
                float Lsky[3];
                const float pdfL = env_radiance(env, envData, d, Lsky);
                const float wMis = !afterSpecular && params.lightSamples > 0u
                                       ? eye_mis_weight(N, pdfB, params.lightSamples, pdfL)
                                       : 1.0f;
                for (int c = 0; c < 3; ++c) Le[c] = Le[c] + T[c] * Lsky[c] * wMis;
            }
            break;
        }
        const PclV3 p = eye_add_scaled(o, d, hit.t);
        travelled += hit.t;
        const PclV3 n = eye_normal(primInfo, hit.prim, params.triangleCount, p, tau);
        const float dn = sampling_dot(d, n);
        const PclV3 nf = dn < 0.0f ? n : sampling_v3(-n.x, -n.y, -n.z);
        const PclPrimInfo info = primInfo[hit.prim];
        const uint mat = info.material;
        PclMaterial M = materials[mat];
        texture_material_at(materialTextures, texels, triangleUvs, mat, hit.prim, params.triangleCount, hit.u, hit.v,
                            &M);

        if (dn < 0.0f && sampling_max3(M.emission[0], M.emission[1], M.emission[2]) > 0.0f &&
            !(afterSpecular && params.causticMapRead != 0u)) {
            /* The BSDF-sampled half of the MIS pair with direct_light: a triangle light reached
             * straight from the eye hit; anything else (spheres, after a specular bounce, no
             * light sampling) counts fully. */
            float wMis = 1.0f;
            const uint l = lightOfPrim[hit.prim];
            if (!afterSpecular && l != PCL_NO_HIT && params.lightSamples > 0u) {
                const PclV3 toQ = sampling_v3(p.x - p0.x, p.y - p0.y, p.z - p0.z);
                const float d2 = sampling_dot(toQ, toQ);
                const float pdfL = eye_area_light_pdf(lights[l], params.areaPowerTotal, d, d2);
                wMis = eye_mis_weight(N, pdfB, params.lightSamples, pdfL);
            }
            for (int c = 0; c < 3; ++c) Le[c] = Le[c] + T[c] * M.emission[c] * wMis;
        }
        const float pd = eye_diffuse_probability(M);
        if (pd < 0.0f) break;
        /* A purely diffuse surface (pd = 1) takes the diffuse lobe for every u0 < 1: its block
         * is drawn only where a specular lobe can be chosen (the same choices, one Philox block
         * fewer per gather ray in most scenes). */
        bool diffuse = pd >= 1.0f;
        if (!diffuse) {
            rng_block(seed, h.pixel, bounceWord, b + 1u, PCL_RNG_STREAM_GATHER, w);
            diffuse = rng_u01(w[0]) < pd;
        }
        if (diffuse) {
            const PclV3 pm = shutter_open_position(info, p, tau); /* the map's place of p */
            q.x = pm.x; q.y = pm.y; q.z = pm.z;
            q.nx = nf.x; q.ny = nf.y; q.nz = nf.z;
            q.maxRadius2 = params.maxRadius2;
            for (int c = 0; c < 3; ++c) out.weight[c] = T[c] * (M.rhoD[c] / PCL_PI_F) / pd;
            if (travelled < params.closeDistance) {
                /* A short gather path: the map's estimate blurs light over a disc as wide as the
                 * path is long (shadow edges, contact shadows next to the eye hit, and under a
                 * mirror ball the contact shadow it reflects). Its direct part by shadow rays,
                 * the map for the rest. */
                const PclV3 ns = shading_normal(triangleNormals, triangleTangents, normalMaps, texels, triangleUvs, mat,
                                                hit.prim, params.triangleCount, hit.u, hit.v, n);
                const PclV3 sf = dn < 0.0f ? ns : sampling_v3(-ns.x, -ns.y, -ns.z);
                float E[3];
                gather_direct(nodes, packets, spheres, primInfo, materials, lights, areaCdf,
                              light_textures(materialTextures, texels, triangleUvs, params.triangleCount), env,
                              envData, &params, seed, h.pixel, bounceWord, tau, p, nf, sf, E);
                for (int c = 0; c < 3; ++c) Le[c] = Le[c] + out.weight[c] * E[c];
                q.k = params.k | PCL_QUERY_NONDIRECT;
            }
            break;
        }
        if (b == params.maxSpecular) break;
        PclV3 dNew;
        float ws[3];
        const PclV3 ns = shading_normal(triangleNormals, triangleTangents, normalMaps, texels, triangleUvs, mat,
                                        hit.prim, params.triangleCount, hit.u, hit.v, n);
        if (!eye_specular_scatter(M, d, n, ns, rng_u01(w[1]), rng_u01(w[2]), rng_u01(w[3]), &dNew, ws)) break;
        const float ps = 1.0f - pd;
        for (int c = 0; c < 3; ++c) T[c] = T[c] * ws[c] / ps;
        o = eye_spawn(p, nf, dNew, params.rayEpsilon);
        d = dNew;
        afterSpecular = true;
    }
    for (int c = 0; c < 3; ++c) {
        out.emitted[c] = isfinite(Le[c]) ? Le[c] : 0.0f;
        if (!isfinite(out.weight[c])) out.weight[c] = 0.0f;
    }
    queries[j] = q;
    gathered[j] = out;
}

/* Optional importance sampling (Jensen 1995, "Importance driven path tracing using the photon
 * map"): the kNN queries at the eye hits (k, maxRadius2 of the params), then per record a G × G
 * histogram of the incident flux of those photons over the cosine map's square, mixed with the
 * uniform (cosine) density: p_c = (1 − α) f_c / Σf + α / G² (α = PCL_GATHER_UNIFORM_MIX), or
 * 1/G² when Σf = 0, stored as its cumulative table cdf[i·G² + c], the last entry 1. A gather
 * ray then takes cell c with u2 < cdf[c] and its point (cx + u0, cy + u1)/G on the square; its
 * density is G² p_c cosθ/π, its weight (and direct light's MIS density) follow. */
__kernel void final_gather_histogram_queries(const PclGatherParams params, __global const PclEyeHit* hits,
                                             __global PclKnnQuery* queries) {
    const uint i = (uint)get_global_id(0);
    if (i >= params.sampleCount) return;
    const PclEyeHit h = hits[i];
    PclKnnQuery q;
    /* At the hit as it is: on a moving surface (photons kept at shutter open, shutter_open.h) it
     * finds fewer photons, which tilts only the importance density toward the uniform mix. */
    q.x = h.x; q.y = h.y; q.z = h.z;
    q.maxRadius2 = (h.flags & PCL_EYE_DIFFUSE) ? params.maxRadius2 : 0.0f;
    q.k = params.k;
    q.pad0 = q.pad1 = q.pad2 = 0u;
    queries[i] = q;
}

__kernel void final_gather_histogram(const PclGatherParams params, __global const PclEyeHit* hits,
                                     __global const PclPhoton* photons, __global const uint* counts,
                                     __global const uint* indices, const uint stride, __global float* histograms) {
    const uint i = (uint)get_global_id(0);
    if (i >= params.sampleCount) return;
    const uint G = params.histogramCells, C = G * G;
    const PclEyeHit h = hits[i];
    float f[PCL_GATHER_MAX_CELLS * PCL_GATHER_MAX_CELLS];
    for (uint c = 0u; c < C; ++c) f[c] = 0.0f;
    float total = 0.0f;
    if (h.flags & PCL_EYE_DIFFUSE) {
        const PclV3 n = sampling_v3(h.snx, h.sny, h.snz); /* the gather rays' frame */
        const uint count = counts[i];
        for (uint j = 0u; j < count; ++j) {
            const PclPhoton ph = photons[indices[(size_t)i * stride + j]];
            const PclV3 wi = photon_dir_decode(ph.packed);
            if (!(sampling_dot(wi, n) > 0.0f)) continue;
            float r, g, b;
            photon_rgbe_decode(ph.rgbe, &r, &g, &b);
            const float flux = eye_luminance(r, g, b);
            f[eye_cell_of_direction(n, wi, G)] += flux;
            total += flux;
        }
    }
    __global float* cdf = histograms + (size_t)i * C;
    float running = 0.0f;
    for (uint c = 0u; c < C; ++c) {
        const float p = total > 0.0f
                            ? (1.0f - PCL_GATHER_UNIFORM_MIX) * (f[c] / total) + PCL_GATHER_UNIFORM_MIX / (float)C
                            : 1.0f / (float)C;
        running += p;
        cdf[c] = c + 1u == C ? 1.0f : running;
    }
}

__kernel void final_gather_resolve(const PclGatherParams params, __global const PclEyeHit* hits,
                                   __global const PclGatherHit* gathered, __global const float* irradiance,
                                   __global PclRadiance* radiance) {
    const uint i = (uint)get_global_id(0);
    if (i >= params.sampleCount) return;
    const PclEyeHit h = hits[i];
    PclRadiance out;
    out.r = out.g = out.b = out.a = 0.0f;
    if (h.flags & PCL_EYE_DIFFUSE) {
        const uint N = params.gatherRays;
        float sum[3] = {0.0f, 0.0f, 0.0f};
        for (uint g = 0u; g < N; ++g) {
            const size_t j = (size_t)i * N + g;
            const PclGatherHit G = gathered[j];
            __global const float* E = irradiance + j * params.irradianceStride;
            for (int c = 0; c < 3; ++c) sum[c] = sum[c] + (G.weight[c] * E[c] + G.emitted[c]);
        }
        float L3[3];
        for (int c = 0; c < 3; ++c) {
            L3[c] = h.throughput[c] * h.albedo[c] * (sum[c] / (float)N);
            if (!isfinite(L3[c])) L3[c] = 0.0f;
        }
        out.r = L3[0];
        out.g = L3[1];
        out.b = L3[2];
    }
    radiance[i] = out;
}
