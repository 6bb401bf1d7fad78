/* eye.h: device helpers the eye-pass kernels share (eye_paths, direct_light, final_gather):
 * surface normals, the diffuse/specular lobe choice, specular scattering and the MIS weight.
 * The rules are kernels/README.md, "Eye pass"; the twins implement them from there. */
#ifndef PCL_EYE_H
#define PCL_EYE_H
#ifdef __OPENCL_VERSION__

#include "types.h"
#include "sampling.h"

inline float eye_luminance(float r, float g, float b) {
    return 0.2126f * r + 0.7152f * g + 0.0722f * b;
}

inline PclV3 eye_add_scaled(PclV3 p, PclV3 d, float t) {
    return sampling_v3(p.x + t * d.x, p.y + t * d.y, p.z + t * d.z);
}

/* The origin of a ray leaving p along d: p moved eps off the surface on the side d goes to. */
inline PclV3 eye_spawn(PclV3 p, PclV3 nf, PclV3 d, float eps) {
    return eye_add_scaled(p, nf, sampling_dot(d, nf) > 0.0f ? eps : -eps);
}

/* The unit outside normal of `prim` at p (spheres placed at shutter time tau). */
inline PclV3 eye_normal(__global const PclPrimInfo* primInfo, uint prim, uint triangleCount, PclV3 p, float tau) {
    const PclPrimInfo info = primInfo[prim];
    if (prim >= triangleCount) {
        const float cx = info.a + info.mx * tau, cy = info.b + info.my * tau, cz = info.c + info.mz * tau;
        return sampling_v3((p.x - cx) / info.radius, (p.y - cy) / info.radius, (p.z - cz) / info.radius);
    }
    return sampling_v3(info.a, info.b, info.c);
}

/* P_d = lum(ρd) / (lum(ρd) + lum(ρs)) (ρs counted when the material has a specular part);
 * negative when both are 0 (a black surface: the path ends). */
inline float eye_diffuse_probability(const PclMaterial M) {
    const float ld = eye_luminance(M.rhoD[0], M.rhoD[1], M.rhoD[2]);
    const float ls = M.specular != PCL_SPECULAR_NONE ? eye_luminance(M.rhoS[0], M.rhoS[1], M.rhoS[2]) : 0.0f;
    const float sum = ld + ls;
    return sum > 0.0f ? ld / sum : -1.0f;
}

/* The specular part of M scatters the unit direction d arriving at a surface with outside
 * geometric normal n and shading normal ns (shared/shading_frame.h; on n's side, = n on flat
 * surfaces): mirror, glossy (Phong lobe about the mirror direction in ns, weight
 * ρs (e+2)/(e+1) cosθ'; false below the surface) or dielectric (reflect when uF < F, weight ρs;
 * else refract, weight ρs η² with η = η_i/η_t, the indices on the path's side (by n) and beyond).
 * Where ns differs from n, a reflection must stay on d's side of the geometric surface and a
 * refraction cross it (false otherwise), as host/reference/bsdf.cpp requires.
 * w gets the weight (before dividing by the lobe choice). */
inline bool eye_specular_scatter(const PclMaterial M, PclV3 d, PclV3 n, PclV3 ns, float uF, float uA, float uB,
                                 PclV3* dNew, float w[3]) {
    const float dn = sampling_dot(d, n);
    const PclV3 sf = dn < 0.0f ? ns : sampling_v3(-ns.x, -ns.y, -ns.z);
    bool crosses = false;
    w[0] = M.rhoS[0];
    w[1] = M.rhoS[1];
    w[2] = M.rhoS[2];
    if (M.specular == PCL_SPECULAR_MIRROR) {
        *dNew = sampling_reflect(d, sf);
    } else if (M.specular == PCL_SPECULAR_GLOSSY) {
        const float e = M.exponent;
        *dNew = sampling_phong_lobe(sampling_reflect(d, sf), e, uA, uB);
        const float cosOut = sampling_dot(*dNew, sf);
        if (!(cosOut > 0.0f)) return false;
        const float f = (e + 2.0f) / (e + 1.0f) * cosOut;
        for (int c = 0; c < 3; ++c) w[c] = w[c] * f;
    } else if (M.specular == PCL_SPECULAR_DIELECTRIC) {
        const float eta = dn < 0.0f ? 1.0f / M.ior : M.ior;
        const float cosI = fabs(sampling_dot(d, ns));
        const float F = sampling_fresnel_dielectric(cosI, eta);
        if (uF < F) {
            *dNew = sampling_reflect(d, sf);
        } else {
            /* Radiance crossing into the path's side scales by (η_i/η_t)² = η² (pbrt-v4's
             * radiance mode): an eye path carries importance, its throughput picks up the factor
             * light undergoes on the way back. Photons (flux) are not scaled. */
            *dNew = sampling_refract(d, sf, cosI, eta);
            crosses = true;
            const float eta2 = eta * eta;
            for (int c = 0; c < 3; ++c) w[c] = w[c] * eta2;
        }
    } else {
        return false;
    }
    if (ns.x != n.x || ns.y != n.y || ns.z != n.z) { /* shading_is_smooth (shared/shading_frame.h) */
        const float side = sampling_dot(*dNew, n) * dn; /* < 0: back to d's side of the surface */
        if (crosses ? !(side > 0.0f) : !(side < 0.0f)) return false;
    }
    return true;
}

/* The normalised Phong lobe of exponent e at a hit reached along d (facing normal nf), toward
 * wi: cos^e α, α the angle between wi and reflect(d, nf); 0 below the surface or outside the
 * lobe. The BRDF is ρs (e+2)/(2π) times this, the lobe's sampling density (e+1)/(2π) times it. */
inline float eye_phong_cos_power(PclV3 d, PclV3 nf, PclV3 wi, float e) {
    if (!(sampling_dot(wi, nf) > 0.0f)) return 0.0f;
    const float cosA = sampling_dot(wi, sampling_reflect(d, nf));
    return cosA > 0.0f ? pow(cosA, e) : 0.0f;
}

/* The power heuristic with sample counts: (nA pA)² / ((nA pA)² + (nB pB)²); 0 when both are 0. */
inline float eye_mis_weight(uint nA, float pA, uint nB, float pB) {
    const float a = (float)nA * pA, b = (float)nB * pB;
    const float a2 = a * a, s = a2 + b * b;
    return s > 0.0f ? a2 / s : 0.0f;
}

/* The solid-angle density with which direct_light samples point q (unit direction wi from the
 * shading point, squared distance d2) on triangle light L: P(L) d² / (A cosθ_L),
 * P(L) = s_L / S, s_L = (Φr + Φg + Φb)/3. 0 when the point sees the back. */
inline float eye_area_light_pdf(const PclLight L, float areaPowerTotal, PclV3 wi, float d2) {
    const float cosL = -(L.axis[0] * wi.x + L.axis[1] * wi.y + L.axis[2] * wi.z);
    if (!(cosL > 0.0f) || !(areaPowerTotal > 0.0f)) return 0.0f;
    const float s = (L.power[0] + L.power[1] + L.power[2]) / 3.0f;
    return (s / areaPowerTotal) * d2 / (L.area * cosL);
}

/* Importance sampling of the gather rays (Jensen 1995; optional): a G × G histogram over the
 * square whose points the cosine-hemisphere map (sampling_cosine_hemisphere, basis
 * sampling_basis(n)) turns into directions. The cell of unit direction w above n: the disk
 * point (w·t, w·b) through the inverse of Shirley & Chiu's concentric map. */
inline uint eye_cell_of_direction(PclV3 n, PclV3 w, uint G) {
    PclV3 t, b;
    sampling_basis(n, &t, &b);
    const float x = sampling_dot(w, t), y = sampling_dot(w, b);
    const float r = sqrt(x * x + y * y);
    float a, c;  /* the square point in [-1, 1]² */
    if (r == 0.0f) {
        a = 0.0f;
        c = 0.0f;
    } else if (fabs(x) > fabs(y)) {
        a = x > 0.0f ? r : -r;
        c = a * (4.0f / PCL_PI_F) * atan2(y / a, x / a);
    } else {
        c = y > 0.0f ? r : -r;
        a = c * (4.0f / PCL_PI_F) * (PCL_PI_F / 2.0f - atan2(y / c, x / c));
    }
    const float s1 = 0.5f * (a + 1.0f), s2 = 0.5f * (c + 1.0f);
    int cx = (int)floor(s1 * (float)G), cy = (int)floor(s2 * (float)G);
    cx = cx < 0 ? 0 : (cx >= (int)G ? (int)G - 1 : cx);
    cy = cy < 0 ? 0 : (cy >= (int)G ? (int)G - 1 : cy);
    return (uint)cy * G + (uint)cx;
}

/* The probability of cell c from the cumulative table: cdf[c] − cdf[c − 1] (cdf[−1] = 0). */
inline float eye_cell_probability(__global const float* cdf, uint c) {
    return c == 0u ? cdf[0] : cdf[c] - cdf[c - 1u];
}

#endif /* __OPENCL_VERSION__ */
#endif /* PCL_EYE_H */
