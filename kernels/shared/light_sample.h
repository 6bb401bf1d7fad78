/* light_sample.h: next-event estimation at a shading point, shared by direct_light (at the
 * diffuse eye record, BRDF ρd/π) and eye_paths (at glossy chain hits, the Phong lobe): the
 * light's incident contribution before the BRDF. Rules: kernels/README.md, "direct light". */
#ifndef PCL_LIGHT_SAMPLE_H
#define PCL_LIGHT_SAMPLE_H
#ifdef __OPENCL_VERSION__

#include "types.h"
#include "sampling.h"
#include "bvh.h"
#include "eye.h"

/* Unoccluded segment from o (already lifted) to o + dir·t, t in (0, tmax). */
inline bool light_visible(__global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                          __global const PclSphere* spheres, PclV3 o, PclV3 dir, float tmax, float tau) {
    const PclRay r = bvh_ray(o.x, o.y, o.z, dir.x, dir.y, dir.z, 0.0f, tmax, tau);
    PclHit hit;
    return !bvh_trace(nodes, packets, spheres, r, true, &hit);
}

inline float light_smoothstep(float e0, float e1, float x) {
    if (e1 <= e0) return x >= e1 ? 1.0f : 0.0f;
    float t = (x - e0) / (e1 - e0);
    t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
    return t * t * (3.0f - 2.0f * t);
}

/* A point, spot or directional light L seen from p (facing normal nf; o = p lifted): the unit
 * direction *wi to it and the factor g with contribution Φ ⊙ g (times the BRDF): cosθ/(πR²)
 * (directional), I/Φ · cosθ/d² (point, spot with its fall-off); 0 when unlit or occluded. */
inline float light_delta(__global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                         __global const PclSphere* spheres, const PclLight L, PclV3 p, PclV3 nf, PclV3 o, float tau,
                         PclV3* wi) {
    if (L.type == PCL_LIGHT_DIRECTIONAL) {
        *wi = sampling_v3(-L.axis[0], -L.axis[1], -L.axis[2]);
        const float cosS = sampling_dot(nf, *wi);
        if (!(cosS > 0.0f)) return 0.0f;
        if (!light_visible(nodes, packets, spheres, o, *wi, INFINITY, tau)) return 0.0f;
        return cosS / (PCL_PI_F * L.radius * L.radius);  /* E = Φ / (π R²) */
    }
    const PclV3 toL = sampling_v3(L.p[0] - p.x, L.p[1] - p.y, L.p[2] - p.z);
    const float d2 = sampling_dot(toL, toL);
    if (!(d2 > 0.0f)) return 0.0f;
    const float dist = sqrt(d2);
    *wi = sampling_v3(toL.x / dist, toL.y / dist, toL.z / dist);
    const float cosS = sampling_dot(nf, *wi);
    if (!(cosS > 0.0f)) return 0.0f;
    float scale;  /* I / Φ × falloff */
    if (L.type == PCL_LIGHT_POINT) {
        scale = 1.0f / (4.0f * PCL_PI_F);
    } else {
        const float cosAxis = -(L.axis[0] * wi->x + L.axis[1] * wi->y + L.axis[2] * wi->z);
        const float falloff = light_smoothstep(L.cosOuter, L.cosInner, cosAxis);
        if (!(falloff > 0.0f)) return 0.0f;
        scale = falloff / (2.0f * PCL_PI_F * ((1.0f - L.cosInner) + 0.5f * (L.cosInner - L.cosOuter)));
    }
    const PclV3 seg = sampling_v3(L.p[0] - o.x, L.p[1] - o.y, L.p[2] - o.z);
    if (!light_visible(nodes, packets, spheres, o, seg, 1.0f, tau)) return 0.0f;
    return scale * cosS / d2;
}

/* One triangle-light sample for p: u0 chooses the light (the first l with u0 < areaCdf[l]),
 * (u1, u2) a point uniform in its area. On success: *wi, the solid-angle density *pdfL, cosθ at
 * p (*cosS) and the light's radiance le[3]; false when the sample is below the surface, on the
 * light's back or occluded. */
inline bool light_area_sample(__global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                              __global const PclSphere* spheres, __global const PclPrimInfo* primInfo,
                              __global const PclMaterial* materials, __global const PclLight* lights,
                              __global const float* areaCdf, uint lightCount, float areaPowerTotal, PclV3 p,
                              PclV3 nf, PclV3 o, float eps, float tau, float u0, float u1, float u2, PclV3* wi,
                              float* pdfL, float* cosS, float le[3]) {
    uint l = 0u;
    while (l + 1u < lightCount && !(u0 < areaCdf[l])) ++l;
    const PclLight L = lights[l];
    if (L.type != PCL_LIGHT_TRIANGLE) return false;
    float b0, b1;
    sampling_uniform_triangle(u1, u2, &b0, &b1);
    const float b2 = 1.0f - b0 - b1;
    const PclV3 q = sampling_v3(L.p[0] + L.e1[0] * b1 + L.e2[0] * b2 + L.motion[0] * tau,
                                L.p[1] + L.e1[1] * b1 + L.e2[1] * b2 + L.motion[1] * tau,
                                L.p[2] + L.e1[2] * b1 + L.e2[2] * b2 + L.motion[2] * tau);
    const PclV3 toL = sampling_v3(q.x - p.x, q.y - p.y, q.z - p.z);
    const float d2 = sampling_dot(toL, toL);
    if (!(d2 > 0.0f)) return false;
    const float dist = sqrt(d2);
    *wi = sampling_v3(toL.x / dist, toL.y / dist, toL.z / dist);
    *cosS = sampling_dot(nf, *wi);
    if (!(*cosS > 0.0f)) return false;
    *pdfL = eye_area_light_pdf(L, areaPowerTotal, *wi, d2);
    if (!(*pdfL > 0.0f)) return false;
    const PclV3 end = sampling_v3(q.x + L.axis[0] * eps, q.y + L.axis[1] * eps, q.z + L.axis[2] * eps);
    const PclV3 seg = sampling_v3(end.x - o.x, end.y - o.y, end.z - o.z);
    if (!light_visible(nodes, packets, spheres, o, seg, 1.0f, tau)) return false;
    const PclMaterial E = materials[primInfo[L.prim].material];
    for (int c = 0; c < 3; ++c) le[c] = E.emission[c];
    return true;
}

#endif /* __OPENCL_VERSION__ */
#endif /* PCL_LIGHT_SAMPLE_H */
