/* camera.cl: camera rays of an eye pass (kernels/README.md, "Eye pass: camera").
 *
 * in:  params      PclCameraParams: camera frame, tan of the half fields of view, thin lens
 *                  (aperture radius, focus distance), pass seed, image size, strata n, the
 *                  launch's sample range, which samplers run
 *      strata      the cells of sample k of the pass's two patterns of n² (stratify.h,
 *                  stratify_cmj_cell): strata[2k], [2k + 1] the lens point's, strata[2n² + 2k],
 *                  [… + 1] (its row) the time's; words 0 and 1 of (PCL_PASS_PATTERN_PATH,
 *                  PCL_CAMERA_PATTERN_BOUNCE, block 0) the patterns
 * out: rays[i]     PclRay of sample s = firstSample + i: pixel = s / n², k = s mod n², stratum
 *                  (k mod n, k div n); unit direction, tmin 0, tmax +inf, time
 *
 * Random numbers: stream CAMERA, path = pixel, bounce = k, dimensions 0..4 = film x, film y,
 * lens u, lens v, time (blocks 0 and 1). The pixel's n² lens points and n² shutter times of a
 * pass are stratified together like the film positions: (lens u, lens v) jitter sample k's cell
 * of the lens pattern, time its row of the time pattern, each pattern shifted for the pixel by
 * words 0, 1 (lens) and 2 (time) of (pixel, PCL_CAMERA_PATTERN_BOUNCE, block 0)
 * (stratify_shifted). */
#include "shared/types.h"
#include "shared/rng.h"
#include "shared/sampling.h"
#include "shared/stratify.h"

#pragma OPENCL FP_CONTRACT OFF

inline PclV3 camera_normalize(PclV3 v) {
    const float inv = 1.0f / sqrt(sampling_dot(v, v));
    return sampling_v3(v.x * inv, v.y * inv, v.z * inv);
}

__kernel void camera_rays(const PclCameraParams P, __global PclRay* rays, __global const uint* strata) {
    const uint i = (uint)get_global_id(0);
    if (i >= P.sampleCount) return;
    const uint n = P.strata, spp = n * n;
    const uint s = P.firstSample + i;
    const uint pixel = s / spp, k = s - pixel * spp;
    const uint x = pixel % P.width, y = pixel / P.width;
    const ulong seed = (ulong)P.seedLo | ((ulong)P.seedHi << 32);
    uint w0[4], w1[4];
    rng_block(seed, pixel, k, 0u, PCL_RNG_STREAM_CAMERA, w0);
    rng_block(seed, pixel, k, 1u, PCL_RNG_STREAM_CAMERA, w1);
    float lensU = rng_u01(w0[2]), lensV = rng_u01(w0[3]), time = rng_u01(w1[0]);
    if (P.lensSampling || P.timeSampling) {
        /* Blur from the lens and the shutter averages over the pixel's samples as the film
         * position does: stratified together, motion-dof's variance fell 1.5x (fg, 4 passes). */
        uint shift[4];
        rng_block(seed, pixel, PCL_CAMERA_PATTERN_BOUNCE, 0u, PCL_RNG_STREAM_CAMERA, shift);
        const uint cells = stratify_cells(spp);
        stratify_shifted(strata[2u * k], strata[2u * k + 1u], cells, spp, lensU, lensV, rng_u01(shift[0]),
                         rng_u01(shift[1]), &lensU, &lensV);
        float row;
        stratify_shifted(strata[2u * (spp + k)], strata[2u * (spp + k) + 1u], cells, spp, 0.5f, time, 0.0f,
                         rng_u01(shift[2]), &row, &time);
    }
    const float filmX = ((float)(k % n) + rng_u01(w0[0])) / (float)n;
    const float filmY = ((float)(k / n) + rng_u01(w0[1])) / (float)n;
    const float sx = (2.0f * ((float)x + filmX) / (float)P.width - 1.0f) * P.tanHalfWidth;
    const float sy = (1.0f - 2.0f * ((float)y + filmY) / (float)P.height) * P.tanHalfHeight;
    const PclV3 F = sampling_v3(P.forward[0], P.forward[1], P.forward[2]);
    const PclV3 R = sampling_v3(P.right[0], P.right[1], P.right[2]);
    const PclV3 U = sampling_v3(P.up[0], P.up[1], P.up[2]);
    PclV3 dir = camera_normalize(sampling_v3(F.x + R.x * sx + U.x * sy, F.y + R.y * sx + U.y * sy,
                                             F.z + R.z * sx + U.z * sy));
    PclV3 o = sampling_v3(P.position[0], P.position[1], P.position[2]);
    if (P.lensSampling) {
        /* Thin lens: the ray from the lens point through the pinhole ray's point on the plane of
         * focus (perpendicular to forward at focusDistance). */
        float lx, ly;
        sampling_concentric_disk(lensU, lensV, &lx, &ly);
        const float tf = P.focusDistance / sampling_dot(dir, F);
        const PclV3 focus = sampling_v3(o.x + dir.x * tf, o.y + dir.y * tf, o.z + dir.z * tf);
        const float a = P.apertureRadius;
        o = sampling_v3(o.x + (R.x * lx + U.x * ly) * a, o.y + (R.y * lx + U.y * ly) * a,
                        o.z + (R.z * lx + U.z * ly) * a);
        dir = camera_normalize(sampling_v3(focus.x - o.x, focus.y - o.y, focus.z - o.z));
    }
    PclRay r;
    r.ox = o.x; r.oy = o.y; r.oz = o.z; r.tmin = 0.0f;
    r.dx = dir.x; r.dy = dir.y; r.dz = dir.z; r.tmax = INFINITY;
    r.time = P.timeSampling ? time : 0.0f;
    r.pad0 = r.pad1 = r.pad2 = 0u;
    rays[i] = r;
}
