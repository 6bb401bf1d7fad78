/* camera.h: a scene point seen by the camera of PclCameraParams (light tracing's connection to
 * the camera, pbrt-v4's PerspectiveCamera::SampleWi): the pixel its light lands in, the lens
 * point it reaches and the importance that turns radiance leaving the point toward the lens into
 * that pixel's average. camera.cl's rays in reverse; the twin is host/reference/camera.h
 * (RayCamera::connect), written independently. In the common subset of C and OpenCL C. */
#ifndef PCL_CAMERA_H
#define PCL_CAMERA_H

#include "sampling.h"
#include "types.h"

/* Point p through lens point (lensU, lensV) (ignored by a pinhole): false when p lies behind
 * the camera or its light falls outside the film. *importance = We G / p_lens without the
 * cosine at p: 1 / (A_pixel cos³θ d²), A_pixel a pixel's area on the film plane at distance 1,
 * θ the angle to the view axis, d the distance from p to the lens point. */
PCL_INLINE int camera_connect(const PclCameraParams* P, PclV3 p, pcl_f32 lensU, pcl_f32 lensV, pcl_u32* pixel,
                              PclV3* lensPoint, pcl_f32* importance) {
    const PclV3 F = sampling_v3(P->forward[0], P->forward[1], P->forward[2]);
    const PclV3 R = sampling_v3(P->right[0], P->right[1], P->right[2]);
    const PclV3 U = sampling_v3(P->up[0], P->up[1], P->up[2]);
    const PclV3 c = sampling_v3(P->position[0], P->position[1], P->position[2]);
    PclV3 lens = c;
    if (P->lensSampling) {
        pcl_f32 lx, ly;
        sampling_concentric_disk(lensU, lensV, &lx, &ly);
        const pcl_f32 a = P->apertureRadius;
        lens = sampling_v3(c.x + (R.x * lx + U.x * ly) * a, c.y + (R.y * lx + U.y * ly) * a,
                           c.z + (R.z * lx + U.z * ly) * a);
    }
    const PclV3 d = sampling_v3(p.x - lens.x, p.y - lens.y, p.z - lens.z);
    const pcl_f32 dist2 = sampling_dot(d, d);
    const pcl_f32 z = sampling_dot(d, F);
    if (!(dist2 > 0.0f) || !(z > 0.0f)) return 0;
    /* The film point whose ray through this lens point heads for p: the pinhole ray toward the
     * point where the line lens → p crosses the plane of focus (for a pinhole, the line itself). */
    PclV3 v = d;
    if (P->lensSampling) {
        const pcl_f32 s = P->focusDistance / z;
        v = sampling_v3(lens.x - c.x + d.x * s, lens.y - c.y + d.y * s, lens.z - c.z + d.z * s);
    }
    const pcl_f32 vz = sampling_dot(v, F);
    if (!(vz > 0.0f)) return 0;
    const pcl_f32 sx = sampling_dot(v, R) / vz, sy = sampling_dot(v, U) / vz;
    const pcl_f32 fx = 0.5f * (sx / P->tanHalfWidth + 1.0f) * (pcl_f32)P->width;
    const pcl_f32 fy = 0.5f * (1.0f - sy / P->tanHalfHeight) * (pcl_f32)P->height;
    if (!(fx >= 0.0f && fx < (pcl_f32)P->width && fy >= 0.0f && fy < (pcl_f32)P->height)) return 0;
    pcl_u32 x = (pcl_u32)fx, y = (pcl_u32)fy;
    x = x < P->width ? x : P->width - 1u;
    y = y < P->height ? y : P->height - 1u;
    *pixel = y * P->width + x;
    *lensPoint = lens;
    const pcl_f32 pixelArea =
        (2.0f * P->tanHalfWidth / (pcl_f32)P->width) * (2.0f * P->tanHalfHeight / (pcl_f32)P->height);
    const pcl_f32 cosTheta = z / PCL_SQRTF(dist2);
    *importance = 1.0f / (pixelArea * cosTheta * cosTheta * cosTheta * dist2);
    return 1;
}

#endif
