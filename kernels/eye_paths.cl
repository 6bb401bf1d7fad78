/* eye_paths.cl: eye rays through specular chains to their first diffuse hit
 * (kernels/README.md, "Eye pass: eye paths" and "Eye pass: media"); one sample per work-item.
 *
 * in:  params                  PclEyeParams: pass seed, samples per pixel n², firstSample,
 *                              sampleCount, triangleCount, maxDepth, rayEpsilon, lightCount,
 *                              areaPowerTotal; media: cameraMedium, volumeSegments (0: no media),
 *                              the scene's bounding sphere
 *      rays[i]                 PclRay of sample s = firstSample + i (camera_rays)
 *      nodes, packets, spheres the BVH; primInfo[prim], materials[]
 *      lights[], areaCdf[l],   next-event estimation at glossy hits (direct_light's light
 *      lightOfPrim[prim]       sampling) and the MIS weight of an emitter the glossy lobe finds
 *      media[], primMedia[prim] participating media (read only when volumeSegments > 0)
 *      env, envData[]          the sky (shared/environment.h): a chain that leaves the scene
 *                              collects its radiance (LE, LS+E); a glossy hit also samples it
 *                              by its map (stream EYE_SKY, path = pixel, bounce = k, block = the
 *                              hit), MIS against the lobe, which weighs the sky it escapes to
 * out: hits[i]                 PclEyeHit: the hit whose diffuse part was chosen (position,
 *                              viewer-side normal, wo, throughput, ρd, material, depth), the
 *                              light the chain collects before it (`emitted`: emission, the
 *                              glossy hits' direct light, single scattering in media), pixel
 *                              and k; prim = PCL_NO_HIT and flags 0 when the chain found none,
 *                              PCL_EYE_TRUNCATED when it ended for want of segment slots
 *      segments[c*sampleCount + i], segmentCounts[i]
 *                              media: the chain's segments in scattering media (PclVolumeSegment,
 *                              c < segmentCounts[i] ≤ volumeSegments), for volume_estimate;
 *                              placeholders never touched without media
 *
 * Media: the ray travels in a medium (start: cameraMedium); invisible boundaries
 * (PCL_MATERIAL_INTERFACE) change it without counting a hit, refraction changes it to the one
 * beyond. Every segment multiplies the throughput by exp(−σt d) per channel; on a segment in a
 * medium with σs > 0 the chain records a PclVolumeSegment (clipped to the bounding sphere when
 * the ray leaves the scene) and adds single scattering by next-event estimation: per delta
 * light one distance (equiangular toward point and spot lights, exponential for directional
 * ones), one triangle-light sample with an equiangular distance toward its point; HG phase;
 * shadow rays through media (shared/eye_medium.h).
 *
 * Random numbers (the reference Sampler's layout): stream CAMERA, path = pixel, bounce = k;
 * at chain hit v (0 = the camera ray's hit) dimension 8 + 8v + 0 chooses a triangle light and
 * + 1, + 2 its point (glossy hits), + 3 the lobe, + 4 and + 5 the glossy direction, + 7
 * reflection or refraction. Single scattering on recorded segment c: stream EYE_MEDIUM, path =
 * pixel, bounce = k, block c (lightCount + 1): u0 triangle light, (u1, u2) its point, u3 the
 * distance; block c (lightCount + 1) + 1 + l: u0 the distance for delta light l. */
#include "shared/types.h"
#include "shared/rng.h"
#include "shared/sampling.h"
#include "shared/bvh.h"
#include "shared/eye.h"
#include "shared/eye_medium.h"
#include "shared/light_sample.h"
#include "shared/environment.h"
#include "shared/texture.h"
#include "shared/shading_frame.h"

#pragma OPENCL FP_CONTRACT OFF

/* Single scattering along o + t d (d unit), t ∈ [0, tEnd] (+∞ when the ray leaves the scene),
 * in medium m (index `medium`), before the path's throughput: per light sample
 * Tr(t) σs p(d·wi) Li tr_shadow / pdf(t) (kernels/README.md, "Eye pass: media"). */
inline void eye_single_scatter(const PclEyeParams params, __global const PclBvhNode* nodes,
                               __global const PclTriPacket* packets, __global const PclSphere* spheres,
                               const EyeMedia em, const LightTextures lt, __global const PclLight* lights,
                               __global const float* areaCdf,
                               const PclMedium m, int medium, PclV3 o, PclV3 d, float tEnd, float tau, ulong seed,
                               uint pixel, uint k, uint segment, float Ls[3]) {
    Ls[0] = Ls[1] = Ls[2] = 0.0f;
    const uint base = segment * (params.lightCount + 1u);
    for (uint l = 0u; l < params.lightCount; ++l) {
        const PclLight L = lights[l];
        if (L.type == PCL_LIGHT_TRIANGLE || L.type == PCL_LIGHT_ENVIRONMENT) continue;
        uint w[4];
        rng_block(seed, pixel, k, base + 1u + l, PCL_RNG_STREAM_EYE_MEDIUM, w);
        const float u = rng_u01(w[0]);
        float t, pdf, scale, tr[3];
        PclV3 wi;
        if (L.type == PCL_LIGHT_DIRECTIONAL) {
            /* Exponential in the channels' mean σt, truncated to [0, tEnd]. */
            const float sbar =
                ((m.sigmaA[0] + m.sigmaS[0]) + (m.sigmaA[1] + m.sigmaS[1]) + (m.sigmaA[2] + m.sigmaS[2])) / 3.0f;
            if (!(sbar > 0.0f)) continue;
            const float mass = tEnd < INFINITY ? -expm1(-sbar * tEnd) : 1.0f;
            if (!(mass > 0.0f)) continue;
            t = -log1p(-u * mass) / sbar;
            t = t > tEnd ? tEnd : t;
            pdf = sbar * exp(-sbar * t) / mass;
            if (!(pdf > 0.0f)) continue;
            wi = sampling_v3(-L.axis[0], -L.axis[1], -L.axis[2]);
            const PclV3 x = eye_add_scaled(o, d, t);
            if (!light_shadow(nodes, packets, spheres, em, medium, x, wi, INFINITY, tau, tr)) continue;
            scale = 1.0f / (PCL_PI_F * L.radius * L.radius); /* E = Φ / (π R²) */
        } else {
            const PclV3 c = sampling_v3(L.p[0], L.p[1], L.p[2]);
            if (!eye_equiangular(o, d, c, tEnd, u, &t, &pdf)) continue;
            const PclV3 x = eye_add_scaled(o, d, t);
            const PclV3 toL = sampling_v3(c.x - x.x, c.y - x.y, c.z - x.z);
            const float d2 = sampling_dot(toL, toL);
            if (!(d2 > 0.0f)) continue;
            const float dist = sqrt(d2);
            wi = sampling_v3(toL.x / dist, toL.y / dist, toL.z / dist);
            scale = light_intensity_scale(L, wi) / d2; /* I / (Φ d²) */
            if (!(scale > 0.0f)) continue;
            if (!light_shadow(nodes, packets, spheres, em, medium, x, toL, 1.0f, tau, tr)) continue;
        }
        float trE[3];
        eye_medium_tr(m, t, trE);
        const float f = eye_hg_phase(sampling_dot(d, wi), m.g) * scale / pdf;
        for (int c = 0; c < 3; ++c) Ls[c] = Ls[c] + trE[c] * m.sigmaS[c] * L.power[c] * tr[c] * f;
    }
    if (!(params.areaPowerTotal > 0.0f)) return;
    uint w[4];
    rng_block(seed, pixel, k, base, PCL_RNG_STREAM_EYE_MEDIUM, w);
    PclLight L;
    PclV3 q;
    float bu, bv;
    if (!light_area_point(lights, areaCdf, params.lightCount, tau, rng_u01(w[0]), rng_u01(w[1]), rng_u01(w[2]), &L,
                          &q, &bu, &bv))
        return;
    float t, pdf;
    if (!eye_equiangular(o, d, q, tEnd, rng_u01(w[3]), &t, &pdf)) return;
    const PclV3 x = eye_add_scaled(o, d, t);
    const PclV3 toL = sampling_v3(q.x - x.x, q.y - x.y, q.z - x.z);
    const float d2 = sampling_dot(toL, toL);
    if (!(d2 > 0.0f)) return;
    const float dist = sqrt(d2);
    const PclV3 wi = sampling_v3(toL.x / dist, toL.y / dist, toL.z / dist);
    const float pdfL = eye_area_light_pdf(L, params.areaPowerTotal, wi, d2);
    if (!(pdfL > 0.0f)) return;
    const PclV3 end = sampling_v3(q.x + L.axis[0] * em.eps, q.y + L.axis[1] * em.eps, q.z + L.axis[2] * em.eps);
    const PclV3 seg = sampling_v3(end.x - x.x, end.y - x.y, end.z - x.z);
    float tr[3];
    if (!light_shadow(nodes, packets, spheres, em, medium, x, seg, 1.0f, tau, tr)) return;
    float Le[3]; /* the light's radiance at q (its emission texture's, if any) */
    light_emission_at(lt, em.primInfo, em.materials, L, bu, bv, Le);
    float trE[3];
    eye_medium_tr(m, t, trE);
    const float f = eye_hg_phase(sampling_dot(d, wi), m.g) / (pdfL * pdf);
    for (int c = 0; c < 3; ++c) Ls[c] = Ls[c] + trE[c] * m.sigmaS[c] * Le[c] * tr[c] * f;
}

__kernel void eye_paths(const PclEyeParams params, __global const PclRay* rays, __global const PclBvhNode* nodes,
                        __global const PclTriPacket* packets, __global const PclSphere* spheres,
                        __global const PclPrimInfo* primInfo, __global const PclMaterial* materials,
                        __global const PclLight* lights, __global const float* areaCdf,
                        __global const uint* lightOfPrim, __global const PclMedium* media,
                        __global const PclPrimMedium* primMedia, __global PclEyeHit* hits,
                        __global PclVolumeSegment* segments, __global uint* segmentCounts, const PclEnvironment env,
                        __global const float* envData, __global const PclMaterialTextures* materialTextures,
                        __global const float* texels, __global const PclTriangleUv* triangleUvs,
                        __global const PclTriangleNormals* triangleNormals, __global const PclNormalMap* normalMaps,
                        __global const PclTriangleTangents* triangleTangents) {
    const uint i = (uint)get_global_id(0);
    if (i >= params.sampleCount) return;
    const uint s = params.firstSample + i;
    const uint pixel = s / params.samplesPerPixel, k = s - pixel * params.samplesPerPixel;
    const ulong seed = (ulong)params.seedLo | ((ulong)params.seedHi << 32);

    const PclRay start = rays[i];
    PclV3 o = sampling_v3(start.ox, start.oy, start.oz);
    PclV3 d = sampling_v3(start.dx, start.dy, start.dz);
    const float tau = start.time;

    PclEyeHit h;
    h.x = h.y = h.z = 0.0f;
    h.time = tau;
    h.nx = h.ny = h.nz = 0.0f;
    h.snx = h.sny = h.snz = 0.0f;
    h.pad0 = 0u;
    h.prim = PCL_NO_HIT;
    h.wox = h.woy = h.woz = 0.0f;
    h.pixel = pixel;
    h.sample = k;
    h.material = 0u;
    h.depth = 0u;
    h.flags = 0u;
    for (int c = 0; c < 4; ++c) h.throughput[c] = h.albedo[c] = h.emitted[c] = 0.0f;

    float T[3] = {1.0f, 1.0f, 1.0f}, Le[3] = {0.0f, 0.0f, 0.0f};
    float pdfLobe = 0.0f;  /* the density with which the last hit's glossy lobe chose d; 0 if not glossy */
    const bool hasMedia = params.volumeSegments > 0u;
    const EyeMedia em = eye_media(primInfo, materials, media, primMedia, params.triangleCount, hasMedia ? 1u : 0u,
                                  params.rayEpsilon);
    const LightTextures lt = light_textures(materialTextures, texels, triangleUvs, params.triangleCount);
    int medium = hasMedia ? params.cameraMedium : PCL_NO_MEDIUM;
    uint segmentCount = 0u, crossings = 0u;
    float travelled = 0.0f; /* media: distance from the last hit to the invisible boundary crossed last */
    for (uint v = 0u; v < params.maxDepth; ++v) {
        const PclRay ray = bvh_ray(o.x, o.y, o.z, d.x, d.y, d.z, 0.0f, INFINITY, tau);
        PclHit hit;
        const bool found = bvh_trace(nodes, packets, spheres, ray, false, &hit);
        if (medium >= 0) {
            /* The segment to the hit (or out of the scene) in this medium. */
            const PclMedium m = media[medium];
            const float tEnd = found ? hit.t : INFINITY;
            if (sampling_max3(m.sigmaS[0], m.sigmaS[1], m.sigmaS[2]) > 0.0f) {
                if (segmentCount >= params.volumeSegments) {
                    h.flags = PCL_EYE_TRUNCATED;
                    break;
                }
                const PclV3 centre = sampling_v3(params.sceneCentre[0], params.sceneCentre[1], params.sceneCentre[2]);
                PclVolumeSegment sg;
                sg.ox = o.x;
                sg.oy = o.y;
                sg.oz = o.z;
                sg.length = found ? hit.t : eye_sphere_exit(o, d, centre, params.sceneRadius);
                sg.dx = d.x;
                sg.dy = d.y;
                sg.dz = d.z;
                sg.time = tau;
                for (int c = 0; c < 3; ++c) sg.throughput[c] = T[c];
                sg.throughput[3] = 0.0f;
                sg.medium = medium;
                sg.record = i;
                sg.pad0 = sg.pad1 = 0u;
                segments[(size_t)segmentCount * params.sampleCount + i] = sg;
                float Ls[3];
                eye_single_scatter(params, nodes, packets, spheres, em, lt, lights, areaCdf, m, medium, o, d, tEnd, tau,
                                   seed, pixel, k, segmentCount, Ls);
                for (int c = 0; c < 3; ++c) Le[c] = Le[c] + T[c] * Ls[c];
                ++segmentCount;
            }
            float tr[3];
            eye_medium_tr(m, tEnd, tr);
            for (int c = 0; c < 3; ++c) T[c] = T[c] * tr[c];
        }
        if (!found) {
            if (env_active(env)) { /* out to the sky; after a glossy lobe, its half of the MIS pair */
                float Lsky[3];
                const float pdfSky = env_radiance(env, envData, d, Lsky);
                const float wE = pdfLobe > 0.0f ? eye_mis_weight(1u, pdfLobe, 1u, pdfSky) : 1.0f;
                for (int c = 0; c < 3; ++c) Le[c] = Le[c] + T[c] * Lsky[c] * wE;
            }
            break;
        }
        const PclV3 p = eye_add_scaled(o, d, hit.t);
        const PclV3 n = eye_normal(primInfo, hit.prim, params.triangleCount, p, tau);
        const float dn = sampling_dot(d, n);
        const PclV3 nf = dn < 0.0f ? n : sampling_v3(-n.x, -n.y, -n.z);
        /* The shading normal (on n's side) and its viewer-side twin sf: the BSDF's frame. */
        const uint mat = primInfo[hit.prim].material;
        const PclV3 ns = shading_normal(triangleNormals, triangleTangents, normalMaps, texels, triangleUvs, mat, hit.prim,
                                        params.triangleCount, hit.u, hit.v, n);
        const PclV3 sf = dn < 0.0f ? ns : sampling_v3(-ns.x, -ns.y, -ns.z);
        PclMaterial M = materials[mat];
        /* The material at the hit (its textures, if any): the lobe choice, the glossy lobe and
         * the record's albedo use it. */
        texture_material_at(materialTextures, texels, triangleUvs, mat, hit.prim, params.triangleCount, hit.u, hit.v,
                            &M);
        if (hasMedia) {
            if ((M.flags & PCL_MATERIAL_INTERFACE) != 0u) {
                /* An invisible boundary: straight on in the medium beyond, not a hit of the chain. */
                medium = dn < 0.0f ? primMedia[hit.prim].inside : primMedia[hit.prim].outside;
                o = eye_add_scaled(p, nf, -params.rayEpsilon);
                travelled = travelled + hit.t;
                if (++crossings >= PCL_MAX_SEGMENTS) {
                    h.flags = PCL_EYE_TRUNCATED;
                    break;
                }
                --v; /* the loop's ++v */
                continue;
            }
            crossings = 0u;
        }

        /* Emission leaves the outside (normal) side only: LE, LS+E. A triangle light reached
         * by a glossy lobe is the lobe's half of the MIS pair with the glossy hit's light sample. */
        if (dn < 0.0f) {
            float wE = 1.0f;
            const uint l = lightOfPrim[hit.prim];
            const float r = travelled + hit.t; /* from the glossy hit, across invisible boundaries */
            if (pdfLobe > 0.0f && l != PCL_NO_HIT && params.areaPowerTotal > 0.0f)
                wE = eye_mis_weight(1u, pdfLobe, 1u, eye_area_light_pdf(lights[l], params.areaPowerTotal, d,
                                                                        r * r));
            for (int c = 0; c < 3; ++c) Le[c] = Le[c] + T[c] * M.emission[c] * wE;
        }

        const float pd = eye_diffuse_probability(M);
        if (pd < 0.0f) break;
        uint wa[4], wb[4];
        rng_block(seed, pixel, k, 2u + 2u * v, PCL_RNG_STREAM_CAMERA, wa);
        rng_block(seed, pixel, k, 3u + 2u * v, PCL_RNG_STREAM_CAMERA, wb);
        /* Direct light through the glossy lobe (next-event estimation, whichever lobe the path
         * takes next): f = ρs (e+2)/(2π) cos^e α; triangle lights by one sample, MIS against the
         * lobe's density (1 − P_d) (e+1)/(2π) cos^e α. */
        if (M.specular == PCL_SPECULAR_GLOSSY && params.lightCount > 0u) {
            const PclV3 lifted = eye_add_scaled(p, nf, params.rayEpsilon);
            const float e = M.exponent;
            float sum[3] = {0.0f, 0.0f, 0.0f};
            for (uint l = 0u; l < params.lightCount; ++l) {
                const PclLight L = lights[l];
                if (L.type == PCL_LIGHT_TRIANGLE || L.type == PCL_LIGHT_ENVIRONMENT) continue;
                PclV3 wi;
                float tr[3];
                const float g = light_delta(nodes, packets, spheres, em, medium, L, p, nf, sf, lifted, tau, &wi, tr);
                if (!(g > 0.0f)) continue;
                const float f = g * eye_phong_cos_power(d, sf, wi, e);
                for (int c = 0; c < 3; ++c) sum[c] = sum[c] + L.power[c] * f * tr[c];
            }
            PclV3 wi;
            float pdfL, cosS, le[3];
            if (params.areaPowerTotal > 0.0f &&
                light_area_sample(nodes, packets, spheres, em, medium, primInfo, materials, lt, lights, areaCdf, params.lightCount,
                                  params.areaPowerTotal, p, nf, sf, lifted, params.rayEpsilon, tau, rng_u01(wa[0]),
                                  rng_u01(wa[1]), rng_u01(wa[2]), &wi, &pdfL, &cosS, le)) {
                const float cp = eye_phong_cos_power(d, sf, wi, e);
                const float pdfB = (1.0f - pd) * ((e + 1.0f) / (2.0f * PCL_PI_F)) * cp;
                const float f = cp * cosS * eye_mis_weight(1u, pdfL, 1u, pdfB) / pdfL;
                for (int c = 0; c < 3; ++c) sum[c] = sum[c] + le[c] * f;
            }
            if (env_active(env)) { /* the sky: one sample by its map, MIS against the lobe */
                uint ws[4];
                rng_block(seed, pixel, k, v, PCL_RNG_STREAM_EYE_SKY, ws);
                PclV3 wsky;
                float pdfSky, cosSky, lsky[3];
                if (light_sky_sample(nodes, packets, spheres, em, medium, env, envData, nf, sf, lifted, tau,
                                     rng_u01(ws[0]), rng_u01(ws[1]), &wsky, &pdfSky, &cosSky, lsky)) {
                    const float cp = eye_phong_cos_power(d, sf, wsky, e);
                    const float pdfB = (1.0f - pd) * ((e + 1.0f) / (2.0f * PCL_PI_F)) * cp;
                    const float f = cp * cosSky * eye_mis_weight(1u, pdfSky, 1u, pdfB) / pdfSky;
                    for (int c = 0; c < 3; ++c) sum[c] = sum[c] + lsky[c] * f;
                }
            }
            const float norm = (e + 2.0f) / (2.0f * PCL_PI_F);
            for (int c = 0; c < 3; ++c) Le[c] = Le[c] + T[c] * M.rhoS[c] * norm * sum[c];
        }
        if (rng_u01(wa[3]) < pd) {  /* the diffuse part: the record */
            h.x = p.x; h.y = p.y; h.z = p.z;
            h.nx = nf.x; h.ny = nf.y; h.nz = nf.z;
            h.snx = sf.x; h.sny = sf.y; h.snz = sf.z;
            h.prim = hit.prim;
            h.wox = -d.x; h.woy = -d.y; h.woz = -d.z;
            for (int c = 0; c < 3; ++c) {
                h.throughput[c] = T[c] / pd;
                h.albedo[c] = M.rhoD[c];
            }
            h.material = mat;
            h.depth = v;
            h.flags = PCL_EYE_DIFFUSE;
            break;
        }
        PclV3 dNew;
        float w[3];
        if (!eye_specular_scatter(M, d, n, ns, rng_u01(wb[3]), rng_u01(wb[0]), rng_u01(wb[1]), &dNew, w)) break;
        /* Through the surface (refraction): the medium on the other side. */
        if (hasMedia && sampling_dot(dNew, n) * dn > 0.0f)
            medium = dn < 0.0f ? primMedia[hit.prim].inside : primMedia[hit.prim].outside;
        const float ps = 1.0f - pd;
        for (int c = 0; c < 3; ++c) T[c] = T[c] * w[c] / ps;
        pdfLobe = M.specular == PCL_SPECULAR_GLOSSY
                      ? ps * ((M.exponent + 1.0f) / (2.0f * PCL_PI_F)) * eye_phong_cos_power(d, sf, dNew, M.exponent)
                      : 0.0f;
        o = eye_spawn(p, nf, dNew, params.rayEpsilon);
        d = dNew;
        travelled = 0.0f;
    }
    for (int c = 0; c < 3; ++c) h.emitted[c] = Le[c];
    /* NaN never escapes: a non-finite record becomes an empty one. */
    bool finite = true;
    for (int c = 0; c < 3; ++c)
        finite = finite && isfinite(h.throughput[c]) && isfinite(h.emitted[c]);
    if (hasMedia)
        for (uint c = 0u; c < segmentCount; ++c) {
            __global const PclVolumeSegment* sg = segments + (size_t)c * params.sampleCount + i;
            for (int ch = 0; ch < 3; ++ch) finite = finite && isfinite(sg->throughput[ch]);
        }
    if (!finite) {
        for (int c = 0; c < 4; ++c) h.throughput[c] = h.emitted[c] = 0.0f;
        h.prim = PCL_NO_HIT;
        h.flags = 0u;
        segmentCount = 0u;
    }
    hits[i] = h;
    if (hasMedia) segmentCounts[i] = segmentCount;
}
