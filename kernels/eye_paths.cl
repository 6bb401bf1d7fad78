/* eye_paths.cl: eye rays through specular chains to their first diffuse hit
 * (kernels/README.md, "Eye pass: eye paths"); one sample per work-item.
 *
 * in:  params                  PclEyeParams: pass seed, samples per pixel n², firstSample,
 *                              sampleCount, triangleCount, maxDepth, rayEpsilon, lightCount,
 *                              areaPowerTotal
 *      rays[i]                 PclRay of sample s = firstSample + i (camera_rays)
 *      nodes, packets, spheres the BVH; primInfo[prim], materials[]
 *      lights[], areaCdf[l],   next-event estimation at glossy hits (direct_light's light
 *      lightOfPrim[prim]       sampling) and the MIS weight of an emitter the glossy lobe finds
 * out: hits[i]                 PclEyeHit: the hit whose diffuse part was chosen (position,
 *                              viewer-side normal, wo, throughput, ρd, material, depth), the
 *                              emitted radiance summed along the chain (with the glossy hits'
 *                              direct light), pixel and k; prim = PCL_NO_HIT and flags 0 when
 *                              the chain found none
 *
 * Random numbers (the reference Sampler's layout): stream CAMERA, path = pixel, bounce = k;
 * at chain hit v (0 = the camera ray's hit) dimension 8 + 8v + 0 chooses a triangle light and
 * + 1, + 2 its point (glossy hits), + 3 the lobe, + 4 and + 5 the glossy direction, + 7
 * reflection or refraction. */
#include "shared/types.h"
#include "shared/rng.h"
#include "shared/sampling.h"
#include "shared/bvh.h"
#include "shared/eye.h"
#include "shared/light_sample.h"

#pragma OPENCL FP_CONTRACT OFF

__kernel void eye_paths(const PclEyeParams params, __global const PclRay* rays, __global const PclBvhNode* nodes,
                        __global const PclTriPacket* packets, __global const PclSphere* spheres,
                        __global const PclPrimInfo* primInfo, __global const PclMaterial* materials,
                        __global const PclLight* lights, __global const float* areaCdf,
                        __global const uint* lightOfPrim, __global PclEyeHit* hits) {
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
    for (uint v = 0u; v < params.maxDepth; ++v) {
        const PclRay ray = bvh_ray(o.x, o.y, o.z, d.x, d.y, d.z, 0.0f, INFINITY, tau);
        PclHit hit;
        if (!bvh_trace(nodes, packets, spheres, ray, false, &hit)) break;
        const PclV3 p = eye_add_scaled(o, d, hit.t);
        const PclV3 n = eye_normal(primInfo, hit.prim, params.triangleCount, p, tau);
        const float dn = sampling_dot(d, n);
        const PclV3 nf = dn < 0.0f ? n : sampling_v3(-n.x, -n.y, -n.z);
        const uint mat = primInfo[hit.prim].material;
        const PclMaterial M = materials[mat];

        /* Emission leaves the outside (normal) side only: LE, LS+E. A triangle light reached
         * by a glossy lobe is the lobe's half of the MIS pair with the glossy hit's light sample. */
        if (dn < 0.0f) {
            float wE = 1.0f;
            const uint l = lightOfPrim[hit.prim];
            if (pdfLobe > 0.0f && l != PCL_NO_HIT && params.areaPowerTotal > 0.0f)
                wE = eye_mis_weight(1u, pdfLobe, 1u, eye_area_light_pdf(lights[l], params.areaPowerTotal, d,
                                                                        hit.t * hit.t));
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
                if (L.type == PCL_LIGHT_TRIANGLE) continue;
                PclV3 wi;
                const float g = light_delta(nodes, packets, spheres, L, p, nf, lifted, tau, &wi);
                if (!(g > 0.0f)) continue;
                const float f = g * eye_phong_cos_power(d, nf, wi, e);
                for (int c = 0; c < 3; ++c) sum[c] = sum[c] + L.power[c] * f;
            }
            PclV3 wi;
            float pdfL, cosS, le[3];
            if (params.areaPowerTotal > 0.0f &&
                light_area_sample(nodes, packets, spheres, primInfo, materials, lights, areaCdf, params.lightCount,
                                  params.areaPowerTotal, p, nf, lifted, params.rayEpsilon, tau, rng_u01(wa[0]),
                                  rng_u01(wa[1]), rng_u01(wa[2]), &wi, &pdfL, &cosS, le)) {
                const float cp = eye_phong_cos_power(d, nf, wi, e);
                const float pdfB = (1.0f - pd) * ((e + 1.0f) / (2.0f * PCL_PI_F)) * cp;
                const float f = cp * cosS * eye_mis_weight(1u, pdfL, 1u, pdfB) / pdfL;
                for (int c = 0; c < 3; ++c) sum[c] = sum[c] + le[c] * f;
            }
            const float norm = (e + 2.0f) / (2.0f * PCL_PI_F);
            for (int c = 0; c < 3; ++c) Le[c] = Le[c] + T[c] * M.rhoS[c] * norm * sum[c];
        }
        if (rng_u01(wa[3]) < pd) {  /* the diffuse part: the record */
            h.x = p.x; h.y = p.y; h.z = p.z;
            h.nx = nf.x; h.ny = nf.y; h.nz = nf.z;
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
        if (!eye_specular_scatter(M, d, n, rng_u01(wb[3]), rng_u01(wb[0]), rng_u01(wb[1]), &dNew, w)) break;
        const float ps = 1.0f - pd;
        for (int c = 0; c < 3; ++c) T[c] = T[c] * w[c] / ps;
        pdfLobe = M.specular == PCL_SPECULAR_GLOSSY
                      ? ps * ((M.exponent + 1.0f) / (2.0f * PCL_PI_F)) * eye_phong_cos_power(d, nf, dNew, M.exponent)
                      : 0.0f;
        o = eye_spawn(p, nf, dNew, params.rayEpsilon);
        d = dNew;
    }
    for (int c = 0; c < 3; ++c) h.emitted[c] = Le[c];
    /* NaN never escapes: a non-finite record becomes an empty one. */
    bool finite = true;
    for (int c = 0; c < 3; ++c)
        finite = finite && isfinite(h.throughput[c]) && isfinite(h.emitted[c]);
    if (!finite) {
        for (int c = 0; c < 4; ++c) h.throughput[c] = h.emitted[c] = 0.0f;
        h.prim = PCL_NO_HIT;
        h.flags = 0u;
    }
    hits[i] = h;
}
