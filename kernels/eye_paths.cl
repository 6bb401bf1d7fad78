/* eye_paths.cl: eye rays through specular chains to their first diffuse hit
 * (kernels/README.md, "Eye pass: eye paths"); one sample per work-item.
 *
 * in:  params                  PclEyeParams: pass seed, samples per pixel n², firstSample,
 *                              sampleCount, triangleCount, maxDepth, rayEpsilon
 *      rays[i]                 PclRay of sample s = firstSample + i (camera_rays)
 *      nodes, packets, spheres the BVH; primInfo[prim], materials[]
 * out: hits[i]                 PclEyeHit: the hit whose diffuse part was chosen (position,
 *                              viewer-side normal, wo, throughput, ρd, material, depth), the
 *                              emitted radiance summed along the chain, pixel and k; prim =
 *                              PCL_NO_HIT and flags 0 when the chain found none
 *
 * Random numbers (the reference Sampler's layout): stream CAMERA, path = pixel, bounce = k;
 * at chain hit v (0 = the camera ray's hit) dimension 8 + 8v + 3 chooses the lobe, 8 + 8v + 4
 * and + 5 the glossy direction, 8 + 8v + 7 reflection or refraction. */
#include "shared/types.h"
#include "shared/rng.h"
#include "shared/sampling.h"
#include "shared/bvh.h"
#include "shared/eye.h"

#pragma OPENCL FP_CONTRACT OFF

__kernel void eye_paths(const PclEyeParams params, __global const PclRay* rays, __global const PclBvhNode* nodes,
                        __global const PclTriPacket* packets, __global const PclSphere* spheres,
                        __global const PclPrimInfo* primInfo, __global const PclMaterial* materials,
                        __global PclEyeHit* hits) {
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

        /* Emission leaves the outside (normal) side only: LE, LS+E. */
        if (dn < 0.0f)
            for (int c = 0; c < 3; ++c) Le[c] = Le[c] + T[c] * M.emission[c];

        const float pd = eye_diffuse_probability(M);
        if (pd < 0.0f) break;
        uint wa[4], wb[4];
        rng_block(seed, pixel, k, 2u + 2u * v, PCL_RNG_STREAM_CAMERA, wa);
        rng_block(seed, pixel, k, 3u + 2u * v, PCL_RNG_STREAM_CAMERA, wb);
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
