/* eye_medium.h: the eye pass in homogeneous participating media (kernels/README.md, "Eye pass:
 * media"), shared by eye_paths and direct_light. The twin is host/reference/eye_medium.h.
 *
 *   EyeMedia                      what a shadow ray needs to cross media; hasMedia 0: a plain
 *                                 visibility test, the pointers unread
 *   eye_shadow_transmittance      Tr along a shadow segment through media and invisible boundaries
 *                                 (PCL_MATERIAL_INTERFACE), 0 at any other surface
 *   eye_equiangular               Kulla & Fajardo 2012: t on [0, tEnd] with density ∝ 1/|x(t) − c|²
 *   eye_hg_phase                  the Henyey–Greenstein phase function
 *   eye_sphere_exit               where a ray leaves the scene's bounding sphere
 *
 * Arithmetic in the twin's order (FP_CONTRACT off), so the twin's floats differ only by the
 * library's exp/atan/tan rounding. */
#ifndef PCL_EYE_MEDIUM_H
#define PCL_EYE_MEDIUM_H
#ifdef __OPENCL_VERSION__

#include "types.h"
#include "sampling.h"
#include "bvh.h"
#include "eye.h"
#include "medium.h"

typedef struct EyeMedia {
    __global const PclPrimInfo* primInfo;
    __global const PclMaterial* materials;
    __global const PclMedium* media;
    __global const PclPrimMedium* primMedia;
    uint triangleCount;
    uint hasMedia;  /* 0: no medium in the scene (the media buffers are placeholders) */
    float eps;      /* offset past an invisible boundary (rayEpsilon) */
} EyeMedia;

inline EyeMedia eye_media(__global const PclPrimInfo* primInfo, __global const PclMaterial* materials,
                          __global const PclMedium* media, __global const PclPrimMedium* primMedia,
                          uint triangleCount, uint hasMedia, float eps) {
    EyeMedia em;
    em.primInfo = primInfo;
    em.materials = materials;
    em.media = media;
    em.primMedia = primMedia;
    em.triangleCount = triangleCount;
    em.hasMedia = hasMedia;
    em.eps = eps;
    return em;
}

/* Per channel exp(−σt len) of medium m (1 where σt = 0, even for an infinite len). */
inline void eye_medium_tr(const PclMedium m, float len, float tr[3]) {
    for (int c = 0; c < 3; ++c) tr[c] = medium_channel_tr(m.sigmaA[c] + m.sigmaS[c], len);
}

/* The transmittance of the shadow segment o + s dir, s ∈ (0, tmax) (dir not necessarily unit),
 * starting in `medium`: closest hits one after another; an invisible boundary switches to the
 * medium beyond (primMedia: inside when dir·n < 0) and the search goes on from p − n_f eps; any
 * other surface blocks. Media multiply exp(−σt · length) per channel (an infinite length in a
 * medium: 0). At most PCL_MAX_SEGMENTS boundaries, then blocked. Returns false when nothing
 * arrives (tr all 0). */
inline bool eye_shadow_transmittance(__global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                                     __global const PclSphere* spheres, const EyeMedia em, int medium, PclV3 o,
                                     PclV3 dir, float tmax, float tau, float tr[3]) {
    tr[0] = tr[1] = tr[2] = 1.0f;
    const float len = sqrt(sampling_dot(dir, dir));
    for (uint crossing = 0u; crossing < PCL_MAX_SEGMENTS; ++crossing) {
        const PclRay r = bvh_ray(o.x, o.y, o.z, dir.x, dir.y, dir.z, 0.0f, tmax, tau);
        PclHit hit;
        const bool found = bvh_trace(nodes, packets, spheres, r, false, &hit);
        const float end = found ? hit.t : tmax;
        if (medium >= 0) {
            float t[3];
            eye_medium_tr(em.media[medium], end * len, t);
            for (int c = 0; c < 3; ++c) tr[c] = tr[c] * t[c];
        }
        if (!found) return sampling_max3(tr[0], tr[1], tr[2]) > 0.0f;
        if ((em.materials[em.primInfo[hit.prim].material].flags & PCL_MATERIAL_INTERFACE) == 0u) break;
        const PclV3 p = eye_add_scaled(o, dir, hit.t);
        const PclV3 n = eye_normal(em.primInfo, hit.prim, em.triangleCount, p, tau);
        const float dn = sampling_dot(dir, n);
        medium = dn < 0.0f ? em.primMedia[hit.prim].inside : em.primMedia[hit.prim].outside;
        const PclV3 nf = dn < 0.0f ? n : sampling_v3(-n.x, -n.y, -n.z);
        o = eye_add_scaled(p, nf, -em.eps);
        tmax = tmax - hit.t;
        if (!(tmax > 0.0f)) return sampling_max3(tr[0], tr[1], tr[2]) > 0.0f;
    }
    tr[0] = tr[1] = tr[2] = 0.0f;
    return false;
}

/* Equiangular sampling (Kulla & Fajardo 2012, "Importance sampling techniques for path tracing
 * in participating media") of t ∈ [0, tEnd] (tEnd may be +∞) along o + t d, d unit, toward the
 * point c: Δ = (c − o)·d, D = |o + Δ d − c|, θ_a = atan2(−Δ, D), θ_b = atan2(tEnd − Δ, D) (π/2 for
 * tEnd = ∞), t = Δ + D tan(θ_a + u (θ_b − θ_a)), pdf = D / ((θ_b − θ_a)(D² + (t − Δ)²)).
 * False when the line passes through c (D = 0) or the interval is empty. */
inline bool eye_equiangular(PclV3 o, PclV3 d, PclV3 c, float tEnd, float u, float* t, float* pdf) {
    const PclV3 oc = sampling_v3(c.x - o.x, c.y - o.y, c.z - o.z);
    const float delta = sampling_dot(oc, d);
    const PclV3 foot = sampling_v3(o.x + delta * d.x - c.x, o.y + delta * d.y - c.y, o.z + delta * d.z - c.z);
    const float D = sqrt(sampling_dot(foot, foot));
    if (!(D > 0.0f)) return false;
    const float thetaA = atan2(-delta, D);
    const float thetaB = tEnd < INFINITY ? atan2(tEnd - delta, D) : 0.5f * PCL_PI_F;
    const float range = thetaB - thetaA;
    if (!(range > 0.0f)) return false;
    const float x = D * tan(thetaA + u * range);
    float s = delta + x;
    s = s < 0.0f ? 0.0f : (s > tEnd ? tEnd : s);
    *t = s;
    *pdf = D / (range * (D * D + x * x));
    return *pdf > 0.0f && isfinite(s);
}

/* p(μ) = (1 − g²) / (4π (1 + g² − 2gμ)^{3/2}), μ the cosine between the directions of travel
 * before and after the scattering. */
inline float eye_hg_phase(float mu, float g) {
    const float denom = 1.0f + g * g - 2.0f * g * mu;
    return (1.0f - g * g) / (4.0f * PCL_PI_F * denom * sqrt(denom > 0.0f ? denom : 0.0f));
}

/* The distance along o + t d (d unit) at which the ray leaves the sphere (centre, radius); 0 when
 * it never is inside it ahead of o. */
inline float eye_sphere_exit(PclV3 o, PclV3 d, PclV3 centre, float radius) {
    const PclV3 oc = sampling_v3(o.x - centre.x, o.y - centre.y, o.z - centre.z);
    const float b = sampling_dot(oc, d);
    const float disc = b * b - (sampling_dot(oc, oc) - radius * radius);
    if (!(disc > 0.0f)) return 0.0f;
    const float t = -b + sqrt(disc);
    return t > 0.0f ? t : 0.0f;
}

#endif /* __OPENCL_VERSION__ */
#endif /* PCL_EYE_MEDIUM_H */
