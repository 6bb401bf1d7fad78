/* sampling.h: the warps and encodings of the photon pass (kernels/README.md fixes every
 * formula here), in the common subset of C and OpenCL C so the host can test them without a
 * device. The CPU twin (host/reference/) does not include this file: it implements the same
 * formulas from the README, independently.
 *
 *   sampling_basis             orthonormal frame around a unit vector (Duff et al. 2017)
 *   sampling_concentric_disk   square -> unit disk (Shirley & Chiu 1997)
 *   sampling_cosine_hemisphere cosine-weighted hemisphere by Malley's method
 *   sampling_uniform_sphere    uniform direction (pbrt-v4 A.5.2)
 *   sampling_uniform_triangle  uniform barycentrics (pbrt-v3 UniformSampleTriangle)
 *   sampling_spot_cos_theta    spot-light cosθ: constant core + smoothstep falloff, inverted
 *   sampling_phong_lobe        cos^n lobe around an axis (Lafortune & Willems 1994)
 *   sampling_fresnel_dielectric exact unpolarised Fresnel reflectance (Born & Wolf)
 *   sampling_reflect / sampling_refract
 *   photon_rgbe_encode/decode  Ward's shared-exponent RGBE (Graphics Gems II, 1991)
 *   photon_dir_encode/decode   (θ, φ) bytes of Jensen's photon record (Jensen 2001, §5.4)
 *
 * Arithmetic is written left to right as the README states it and FP_CONTRACT is off on the
 * device, so a twin that follows the README gets the same floats up to the library functions'
 * rounding (cos, sin, pow, acos, atan2). */
#ifndef PCL_SAMPLING_H
#define PCL_SAMPLING_H

#include "compat.h"

#if PCL_DEVICE
  #pragma OPENCL FP_CONTRACT OFF
  #define PCL_SQRTF(x) sqrt(x)
  #define PCL_COSF(x) cos(x)
  #define PCL_SINF(x) sin(x)
  #define PCL_POWF(x, y) pow(x, y)
  #define PCL_ACOSF(x) acos(x)
  #define PCL_ATAN2F(y, x) atan2(y, x)
  #define PCL_FLOORF(x) floor(x)
  #define PCL_FABSF(x) fabs(x)
  #define PCL_COPYSIGNF(x, y) copysign(x, y)
  #define PCL_FREXPF(x, e) frexp(x, e)
  #define PCL_LDEXPF(x, e) ldexp(x, e)
#else
  #define PCL_SQRTF(x) sqrtf(x)
  #define PCL_COSF(x) cosf(x)
  #define PCL_SINF(x) sinf(x)
  #define PCL_POWF(x, y) powf(x, y)
  #define PCL_ACOSF(x) acosf(x)
  #define PCL_ATAN2F(y, x) atan2f(y, x)
  #define PCL_FLOORF(x) floorf(x)
  #define PCL_FABSF(x) fabsf(x)
  #define PCL_COPYSIGNF(x, y) copysignf(x, y)
  #define PCL_FREXPF(x, e) frexpf(x, e)
  #define PCL_LDEXPF(x, e) ldexpf(x, e)
#endif

/* cos and sin of one angle: on the device one argument reduction instead of two (PoCL spends
 * a sizeable share of the photon pass reducing arguments). */
#if PCL_DEVICE
  #define PCL_SINCOSF(x, s, c) (*(s) = sincos(x, c))
#else
  #define PCL_SINCOSF(x, s, c) (*(s) = sinf(x), *(c) = cosf(x))
#endif

#define PCL_PI_F 3.14159265358979323846f
#define PCL_TWO_PI_F 6.28318530717958647692f

/* Three floats by value: a local helper, never a buffer struct (no float3 in buffers: types.h). */
typedef struct PclV3 {
    pcl_f32 x, y, z;
} PclV3;

PCL_INLINE PclV3 sampling_v3(pcl_f32 x, pcl_f32 y, pcl_f32 z) {
    PclV3 v;
    v.x = x;
    v.y = y;
    v.z = z;
    return v;
}

PCL_INLINE pcl_f32 sampling_dot(PclV3 a, PclV3 b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

PCL_INLINE pcl_f32 sampling_max3(pcl_f32 a, pcl_f32 b, pcl_f32 c) {
    pcl_f32 m = a > b ? a : b;
    return m > c ? m : c;
}

/* Duff, Burgess, Christensen, Hery, Kensler, Liani, Villemin, "Building an Orthonormal Basis,
 * Revisited", JCGT 6(1), 2017, listing 3: no branch on the sign but copysign. */
PCL_INLINE void sampling_basis(PclV3 n, PclV3* t, PclV3* b) {
    pcl_f32 s = PCL_COPYSIGNF(1.0f, n.z);
    pcl_f32 a = -1.0f / (s + n.z);
    pcl_f32 c = n.x * n.y * a;
    t->x = 1.0f + s * n.x * n.x * a;
    t->y = s * c;
    t->z = -s * n.x;
    b->x = c;
    b->y = s + n.y * n.y * a;
    b->z = -n.y;
}

/* x t + y b + z n, per component left to right. */
PCL_INLINE PclV3 sampling_from_frame(PclV3 t, PclV3 b, PclV3 n, pcl_f32 x, pcl_f32 y, pcl_f32 z) {
    return sampling_v3(x * t.x + y * b.x + z * n.x, x * t.y + y * b.y + z * n.y,
                       x * t.z + y * b.z + z * n.z);
}

/* sin and cos of |t| ≤ π/4 by their Taylor polynomials to t⁹ and t¹⁰ (truncation below 2e-9,
 * under half an ulp), in Horner form: no argument reduction and no library call, which PoCL
 * runs as a long scalar chain per work-item (a sizeable share of the photon pass), and the same
 * floats on both sides (FP_CONTRACT is off on the device). */
PCL_INLINE void sampling_sincos_quarter(pcl_f32 t, pcl_f32* s, pcl_f32* c) {
    const pcl_f32 t2 = t * t;
    *s = t * (1.0f + t2 * (-1.0f / 6.0f + t2 * (1.0f / 120.0f + t2 * (-1.0f / 5040.0f + t2 * (1.0f / 362880.0f)))));
    *c = 1.0f + t2 * (-0.5f + t2 * (1.0f / 24.0f + t2 * (-1.0f / 720.0f + t2 * (1.0f / 40320.0f + t2 * (-1.0f / 3628800.0f)))));
}

/* Shirley & Chiu, "A Low Distortion Map Between Disk and Square", JGT 2(3), 1997, in the
 * polar form of pbrt-v3 ConcentricSampleDisk. Its angle is t or π/2 − t with |t| ≤ π/4, so the
 * quarter-range sin and cos serve (cos(π/2 − t) = sin t). */
PCL_INLINE void sampling_concentric_disk(pcl_f32 s1, pcl_f32 s2, pcl_f32* x, pcl_f32* y) {
    pcl_f32 a = 2.0f * s1 - 1.0f;
    pcl_f32 b = 2.0f * s2 - 1.0f;
    if (a == 0.0f && b == 0.0f) {
        *x = 0.0f;
        *y = 0.0f;
        return;
    }
    pcl_f32 st, ct;
    if (PCL_FABSF(a) > PCL_FABSF(b)) {
        sampling_sincos_quarter((PCL_PI_F / 4.0f) * (b / a), &st, &ct);
        *x = a * ct;
        *y = a * st;
    } else {
        sampling_sincos_quarter((PCL_PI_F / 4.0f) * (a / b), &st, &ct);
        *x = b * st;
        *y = b * ct;
    }
}

/* Malley's method: a uniform point on the disk lifted to the hemisphere has density cosθ/π. */
PCL_INLINE PclV3 sampling_cosine_hemisphere(PclV3 n, pcl_f32 s1, pcl_f32 s2) {
    pcl_f32 x, y;
    sampling_concentric_disk(s1, s2, &x, &y);
    pcl_f32 zz = 1.0f - x * x - y * y;
    pcl_f32 z = PCL_SQRTF(zz > 0.0f ? zz : 0.0f);
    PclV3 t, b;
    sampling_basis(n, &t, &b);
    return sampling_from_frame(t, b, n, x, y, z);
}

/* Uniform on the unit sphere, density 1/(4π): z = 1 - 2 s1, φ = 2π s2. */
PCL_INLINE PclV3 sampling_uniform_sphere(pcl_f32 s1, pcl_f32 s2) {
    pcl_f32 z = 1.0f - 2.0f * s1;
    pcl_f32 rr = 1.0f - z * z;
    pcl_f32 r = PCL_SQRTF(rr > 0.0f ? rr : 0.0f);
    pcl_f32 phi = PCL_TWO_PI_F * s2;
    pcl_f32 sp, cp;
    PCL_SINCOSF(phi, &sp, &cp);
    return sampling_v3(r * cp, r * sp, z);
}

/* Uniform barycentrics: b0 = 1 - √u1, b1 = u2 √u1 (weights of p0 and p1). */
PCL_INLINE void sampling_uniform_triangle(pcl_f32 u1, pcl_f32 u2, pcl_f32* b0, pcl_f32* b1) {
    pcl_f32 su = PCL_SQRTF(u1);
    *b0 = 1.0f - su;
    *b1 = u2 * su;
}

/* The normalised integral of smoothstep over [0, t]: 2t³ - t⁴ = t³ (2 - t). */
PCL_INLINE pcl_f32 sampling_smoothstep_cdf(pcl_f32 t) {
    return t * t * t * (2.0f - t);
}

/* Spot-light cosθ with density proportional to the falloff (kernels/README.md, "Spot cosθ"):
 * the core [cosInner, 1] has weight w_in = 1 - cosInner, the smoothstep falloff
 * [cosOuter, cosInner] weight w_fall = (cosInner - cosOuter)/2. The falloff part inverts its
 * CDF 2t³ - t⁴ by 32 float bisections (the CDF is monotone, so bisection cannot fail). */
PCL_INLINE pcl_f32 sampling_spot_cos_theta(pcl_f32 s1, pcl_f32 cosInner, pcl_f32 cosOuter) {
    pcl_f32 wIn = 1.0f - cosInner;
    pcl_f32 wFall = (cosInner - cosOuter) / 2.0f;
    pcl_f32 pIn = wIn / (wIn + wFall);
    if (s1 < pIn) return 1.0f - (s1 / pIn) * wIn;
    pcl_f32 v = (s1 - pIn) / (1.0f - pIn);
    pcl_f32 lo = 0.0f, hi = 1.0f;
    for (int k = 0; k < 32; ++k) {
        pcl_f32 mid = 0.5f * (lo + hi);
        if (sampling_smoothstep_cdf(mid) < v)
            lo = mid;
        else
            hi = mid;
    }
    pcl_f32 t = 0.5f * (lo + hi);
    return cosOuter + t * (cosInner - cosOuter);
}

/* A direction at angle θ (given as cosθ) from axis, azimuth φ, in makeBasis(axis). */
PCL_INLINE PclV3 sampling_cone_direction(PclV3 axis, pcl_f32 cosTheta, pcl_f32 phi) {
    pcl_f32 ss = 1.0f - cosTheta * cosTheta;
    pcl_f32 sinTheta = PCL_SQRTF(ss > 0.0f ? ss : 0.0f);
    PclV3 t, b;
    sampling_basis(axis, &t, &b);
    pcl_f32 sp, cp;
    PCL_SINCOSF(phi, &sp, &cp);
    return sampling_from_frame(t, b, axis, sinTheta * cp, sinTheta * sp, cosTheta);
}

/* cosⁿ lobe around r: cosα = u^(1/(n+1)), φ = 2π v; density (n+1)/(2π) cosⁿα. */
PCL_INLINE PclV3 sampling_phong_lobe(PclV3 r, pcl_f32 exponent, pcl_f32 u, pcl_f32 v) {
    pcl_f32 cosA = PCL_POWF(u, 1.0f / (exponent + 1.0f));
    return sampling_cone_direction(r, cosA, PCL_TWO_PI_F * v);
}

/* Mirror d about n: d - 2 (d·n) n. */
PCL_INLINE PclV3 sampling_reflect(PclV3 d, PclV3 n) {
    pcl_f32 k = 2.0f * sampling_dot(d, n);
    return sampling_v3(d.x - k * n.x, d.y - k * n.y, d.z - k * n.z);
}

/* Exact unpolarised Fresnel reflectance for cosθ_i and η = η_i/η_t; 1 under total internal
 * reflection. r_s = (η cos_i - cos_t)/(η cos_i + cos_t), r_p = (cos_i - η cos_t)/(cos_i + η cos_t)
 * (the Fresnel equations divided through by η_t), F = (r_s² + r_p²)/2. */
PCL_INLINE pcl_f32 sampling_fresnel_dielectric(pcl_f32 cosI, pcl_f32 eta) {
    pcl_f32 sin2T = eta * eta * (1.0f - cosI * cosI);
    if (sin2T >= 1.0f) return 1.0f;
    pcl_f32 cosT = PCL_SQRTF(1.0f - sin2T);
    pcl_f32 rs = (eta * cosI - cosT) / (eta * cosI + cosT);
    pcl_f32 rp = (cosI - eta * cosT) / (cosI + eta * cosT);
    return 0.5f * (rs * rs + rp * rp);
}

/* Refraction of d through a surface whose normal nf faces d's side (d·nf < 0), cos_i = |d·n|:
 * d' = η d + (η cos_i - cos_t) nf, cos_t = √(1 - η²(1 - cos_i²)). The caller has ruled out
 * total internal reflection (the Fresnel term is 1 there). */
PCL_INLINE PclV3 sampling_refract(PclV3 d, PclV3 nf, pcl_f32 cosI, pcl_f32 eta) {
    pcl_f32 c2 = 1.0f - eta * eta * (1.0f - cosI * cosI);
    pcl_f32 cosT = PCL_SQRTF(c2 > 0.0f ? c2 : 0.0f);
    pcl_f32 k = eta * cosI - cosT;
    return sampling_v3(eta * d.x + k * nf.x, eta * d.y + k * nf.y, eta * d.z + k * nf.z);
}

/* ---- Photon record encodings (kernels/README.md, "Photon record") ---------------------- */

/* min(255, max(0, ⌊x⌋)) as a byte, NaN to 0, by a conversion instead of floor (PoCL's floor is a
 * branchy software routine): for 1 <= x < 256 truncation is the floor, and every other x lands
 * on 0 or 255 either way. */
PCL_INLINE pcl_u32 photon_floor_to_byte(pcl_f32 x) {
    return x >= 256.0f ? 255u : (x >= 1.0f ? (pcl_u32)x : 0u);
}

/* Ward's RGBE: the largest channel sets a shared exponent, each channel keeps 8 bits (the
 * channel byte min(255, max(0, ⌊c·scale + 0.5⌋))). */
PCL_INLINE pcl_u32 photon_rgbe_encode(pcl_f32 r, pcl_f32 g, pcl_f32 b) {
    pcl_f32 v = sampling_max3(r, g, b);
    if (!(v >= 1e-32f)) return 0u;
    int e;
    pcl_f32 m = PCL_FREXPF(v, &e);
    pcl_f32 scale = m * 256.0f / v;
    pcl_u32 br = photon_floor_to_byte(r * scale + 0.5f);
    pcl_u32 bg = photon_floor_to_byte(g * scale + 0.5f);
    pcl_u32 bb = photon_floor_to_byte(b * scale + 0.5f);
    pcl_u32 be = (pcl_u32)(e + 128);
    return br | (bg << 8) | (bb << 16) | (be << 24);
}

/* c = byte · 2^(E - 136); rgbe 0 decodes to black. */
PCL_INLINE void photon_rgbe_decode(pcl_u32 rgbe, pcl_f32* r, pcl_f32* g, pcl_f32* b) {
    pcl_u32 be = rgbe >> 24;
    if (be == 0u) {
        *r = *g = *b = 0.0f;
        return;
    }
    int e = (int)be - 136;
    *r = PCL_LDEXPF((pcl_f32)(rgbe & 255u), e);
    *g = PCL_LDEXPF((pcl_f32)((rgbe >> 8) & 255u), e);
    *b = PCL_LDEXPF((pcl_f32)((rgbe >> 16) & 255u), e);
}

/* acos and atan2 to within 1e-6 radians, for photon_dir_encode's fast path (PoCL's scalar acos
 * and atan2 were a seventh of trace_photons' CPU samples under perf). acos: Abramowitz & Stegun 4.4.46,
 * acos(a) = √(1 - a) (a0 + ... + a7 a⁷) + ε, |ε| ≤ 2e-8 on [0, 1], with acos(-a) = π - acos(a).
 * atan: t Q(t²) on [0, 1], a degree-6 Q fitted by iteratively reweighted least squares (Lawson),
 * |error| ≤ 2.6e-7 in float coefficients, with the octant folded in afterwards. */
PCL_INLINE pcl_f32 sampling_acos_approx(pcl_f32 z) {
    pcl_f32 a = PCL_FABSF(z);
    pcl_f32 p = -0.0012624911f;
    p = p * a + 0.0066700901f;
    p = p * a - 0.0170881256f;
    p = p * a + 0.0308918810f;
    p = p * a - 0.0501743046f;
    p = p * a + 0.0889789874f;
    p = p * a - 0.2145988016f;
    p = p * a + 1.5707963050f;
    pcl_f32 r = PCL_SQRTF(1.0f - a) * p;
    return z < 0.0f ? PCL_PI_F - r : r;
}
PCL_INLINE pcl_f32 sampling_atan2_approx(pcl_f32 y, pcl_f32 x) {
    pcl_f32 ax = PCL_FABSF(x), ay = PCL_FABSF(y);
    pcl_f32 t = ay > ax ? ax / ay : ay / ax;
    pcl_f32 s = t * t;
    pcl_f32 q = 0.00681179296f;
    q = q * s - 0.0336042196f;
    q = q * s + 0.0796236694f;
    q = q * s - 0.132333428f;
    q = q * s + 0.198078156f;
    q = q * s - 0.333173692f;
    q = q * s + 0.999996126f;
    pcl_f32 a = t * q;
    if (ay > ax) a = PCL_PI_F / 2.0f - a;
    if (x < 0.0f) a = PCL_PI_F - a;
    return y < 0.0f ? -a : a;
}

/* Whether ⌊V⌋ can be read off v, an approximation of V with |v - V| well below
 * PCL_DIR_BYTE_MARGIN: true, with *f = ⌊v⌋ = ⌊V⌋, when v is more than the margin away from an
 * integer; false near a bin edge, at an exact edge (φ = ±π, w_z = ±1), and for NaN, where the
 * caller computes V with the library. The margin covers the approximation (≤ 1e-6 rad, ≤ 1e-4
 * in bytes) and the library's own rounding (acos and atan2 within a few ulp), 10× over:
 * tests/unit/shared_sampling_test.cpp checks every float w_z for θ, and directions beside every
 * φ edge, against the library. */
#define PCL_DIR_BYTE_MARGIN 2e-3f
PCL_INLINE int sampling_floor_if_clear(pcl_f32 v, pcl_f32* f) {
    *f = PCL_FLOORF(v);
    pcl_f32 frac = v - *f;
    return frac > PCL_DIR_BYTE_MARGIN && frac < 1.0f - PCL_DIR_BYTE_MARGIN;
}

/* θ byte = min(255, ⌊acos(w_z)·256/π⌋), φ byte = ⌊atan2(w_y, w_x)·128/π⌋ & 255; returns
 * θ | φ << 8 (the low half of PclPhoton::packed). The bytes are those of the library acos and
 * atan2, which are called only where the approximations are too close to a bin edge to tell
 * (about 0.4 % of calls each for uniform directions). The fast path scales by 256/π and 128/π
 * as constants, a multiply instead of a division: one more rounding, inside the margin. */
PCL_INLINE pcl_u32 photon_dir_encode(pcl_f32 wx, pcl_f32 wy, pcl_f32 wz) {
    pcl_f32 z = wz > 1.0f ? 1.0f : (wz < -1.0f ? -1.0f : wz);
    pcl_f32 th, pf;
    if (!sampling_floor_if_clear(sampling_acos_approx(z) * (256.0f / PCL_PI_F), &th))
        th = PCL_FLOORF(PCL_ACOSF(z) * 256.0f / PCL_PI_F);
    pcl_u32 theta = th > 255.0f ? 255u : (th > 0.0f ? (pcl_u32)th : 0u);
    if (!sampling_floor_if_clear(sampling_atan2_approx(wy, wx) * (128.0f / PCL_PI_F), &pf))
        pf = PCL_FLOORF(PCL_ATAN2F(wy, wx) * 128.0f / PCL_PI_F);
    pcl_u32 phi = ((pcl_u32)(pcl_i32)pf) & 255u;
    return theta | (phi << 8);
}

/* The direction at the centre of a (θ, φ) byte cell, as Jensen's lookup tables (§5.4). */
PCL_INLINE PclV3 photon_dir_decode(pcl_u32 packed) {
    pcl_f32 theta = ((pcl_f32)(packed & 255u) + 0.5f) * (PCL_PI_F / 256.0f);
    pcl_u32 pb = (packed >> 8) & 255u;
    pcl_i32 ps = pb >= 128u ? (pcl_i32)pb - 256 : (pcl_i32)pb;
    pcl_f32 phi = ((pcl_f32)ps + 0.5f) * (PCL_PI_F / 128.0f);
    pcl_f32 st = PCL_SINF(theta);
    return sampling_v3(st * PCL_COSF(phi), st * PCL_SINF(phi), PCL_COSF(theta));
}

/* Octahedral unit vector (Meyer et al. 2010), u and v rounded to snorm16: u | v << 16.
 * s = |x| + |y| + |z|, (u, v) = (x, y)/s; below the equator (z < 0) folded to
 * ((1 − |v|) sgn u, (1 − |u|) sgn v) with sgn 0 = +1; q = ⌊clamp(·, −1, 1)·32767 + 0.5⌋. */
PCL_INLINE pcl_u32 photon_snorm16(pcl_f32 c) {
    pcl_f32 q = PCL_FLOORF((c > 1.0f ? 1.0f : (c < -1.0f ? -1.0f : c)) * 32767.0f + 0.5f);
    return ((pcl_u32)(pcl_i32)q) & 0xFFFFu;
}
PCL_INLINE pcl_u32 photon_normal_encode(pcl_f32 x, pcl_f32 y, pcl_f32 z) {
    pcl_f32 s = PCL_FABSF(x) + PCL_FABSF(y) + PCL_FABSF(z);
    pcl_f32 u = s > 0.0f ? x / s : 0.0f, v = s > 0.0f ? y / s : 0.0f;
    if (z < 0.0f) {
        pcl_f32 fu = (1.0f - PCL_FABSF(v)) * (u >= 0.0f ? 1.0f : -1.0f);
        pcl_f32 fv = (1.0f - PCL_FABSF(u)) * (v >= 0.0f ? 1.0f : -1.0f);
        u = fu;
        v = fv;
    }
    return photon_snorm16(u) | (photon_snorm16(v) << 16);
}
/* The unit normal of a photon_normal_encode word. */
PCL_INLINE PclV3 photon_normal_decode(pcl_u32 w) {
    pcl_f32 u = (pcl_f32)(pcl_i32)(short)(w & 0xFFFFu) / 32767.0f;
    pcl_f32 v = (pcl_f32)(pcl_i32)(short)(w >> 16) / 32767.0f;
    pcl_f32 z = 1.0f - PCL_FABSF(u) - PCL_FABSF(v);
    if (z < 0.0f) {
        pcl_f32 fu = (1.0f - PCL_FABSF(v)) * (u >= 0.0f ? 1.0f : -1.0f);
        pcl_f32 fv = (1.0f - PCL_FABSF(u)) * (v >= 0.0f ? 1.0f : -1.0f);
        u = fu;
        v = fv;
    }
    pcl_f32 l = PCL_SQRTF(u * u + v * v + z * z);
    return sampling_v3(u / l, v / l, z / l);
}

#endif /* PCL_SAMPLING_H */
