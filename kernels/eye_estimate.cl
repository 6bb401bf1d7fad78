/* eye_estimate.cl: photon-map estimates at the diffuse eye hits — the caustic map (LS+DE), or
 * the global map for the direct-visualisation preview (kernels/README.md, "Eye pass: estimates
 * at the eye hits").
 *
 * eye_estimate_queries — in: params (sampleCount, k, maxRadius2, minDepth, atShutterOpen), hits[i]
 *   (PclEyeHit), primInfo (the motion of the hit's primitive, read when atShutterOpen);
 *   out: queries[i] PclEstimateQuery at the hit (with atShutterOpen, on a moving surface, where
 *   the surface sits at shutter open) with its viewer-side normal; maxRadius2 = 0
 *   (nothing found) at the origin for records without a diffuse hit or with fewer than
 *   minDepth specular bounces before it (caustic connections light those: connect_caustics.cl).
 * eye_estimate_resolve — in: params (irradianceStride, minDepth), hits[i], irradiance (stride
 *   floats per query, rgb first); out: radiance[i] = throughput × ρd × E / π, 0 where the
 *   query was empty. */
#include "shared/types.h"
#include "shared/sampling.h"
#include "shared/shutter_open.h"

#pragma OPENCL FP_CONTRACT OFF

__kernel void eye_estimate_queries(const PclEyeEstimateParams params, __global const PclEyeHit* hits,
                                   __global const PclPrimInfo* primInfo, __global PclEstimateQuery* queries) {
    const uint i = (uint)get_global_id(0);
    if (i >= params.sampleCount) return;
    const PclEyeHit h = hits[i];
    PclEstimateQuery q;
    q.k = params.k;
    if ((h.flags & PCL_EYE_DIFFUSE) && h.depth >= params.minDepth) {
        PclV3 p = sampling_v3(h.x, h.y, h.z);
        if (params.atShutterOpen) p = shutter_open_position(primInfo[h.prim], p, h.time);
        q.x = p.x; q.y = p.y; q.z = p.z;
        q.nx = h.nx; q.ny = h.ny; q.nz = h.nz;
        q.maxRadius2 = params.maxRadius2;
    } else {
        q.x = q.y = q.z = 0.0f;
        q.nx = 0.0f; q.ny = 0.0f; q.nz = 1.0f;
        q.maxRadius2 = 0.0f;
    }
    queries[i] = q;
}

__kernel void eye_estimate_resolve(const PclEyeEstimateParams params, __global const PclEyeHit* hits,
                                   __global const float* irradiance, __global PclRadiance* radiance) {
    const uint i = (uint)get_global_id(0);
    if (i >= params.sampleCount) return;
    const PclEyeHit h = hits[i];
    __global const float* E = irradiance + (size_t)i * params.irradianceStride;
    float L3[3] = {0.0f, 0.0f, 0.0f};
    if ((h.flags & PCL_EYE_DIFFUSE) && h.depth >= params.minDepth)
        for (int c = 0; c < 3; ++c) {
            L3[c] = h.throughput[c] * h.albedo[c] * E[c] / PCL_PI_F;
            if (!isfinite(L3[c])) L3[c] = 0.0f;
        }
    PclRadiance out;
    out.r = L3[0];
    out.g = L3[1];
    out.b = L3[2];
    out.a = 0.0f;
    radiance[i] = out;
}
