/* environment.h: the environment light ("sky", scene.h Environment) as the photon methods read
 * it, on the device and in the CPU twins alike (one header, so both look up the same texels and
 * sample the same directions from the same tables; host/prep/environment_buffers builds them).
 *
 * Mapping (prep/environment_map.h, Mitsuba 3's envmap): a direction w in the sky's own frame
 * (the world turned back by the rotation about +y) falls in texel
 *   u = atan2(w.x, −w.z) / 2π (wrapped to [0, 1)),  v = acos(w.y) / π (row 0 looks up);
 * nearest texel. A constant sky is one 1 × 1 texel. Importance sampling (exact, piecewise
 * constant): a row by rowCdf, a column by that row's columnCdf, then a direction uniform in the
 * texel's solid angle (φ uniform, cos θ uniform). Each texel's weight is its luminance Y
 * (Rec. 709: 0.2126 R + 0.7152 G + 0.0722 B, > 0 wherever any channel is) times its solid angle,
 * so the density is
 *   p(w) = Y(L(w)) / I,   I = ∫ Y(L) dω  (PclEnvironment.integral),
 * and a sample's radiance over its density is L_c(w) · I / Y(L(w)) per channel.
 *
 * data[] (floats): texels rgb (scale applied) at 3 (y W + x); rowCdf[H + 1] at rowCdfOffset
 * (0 … 1); per row y, columnCdf[W + 1] at columnCdfOffset + y (W + 1) (0 … 1). */
#ifndef PCL_ENVIRONMENT_H
#define PCL_ENVIRONMENT_H

#include "compat.h"
#include "sampling.h"

typedef struct PclEnvironment {
    pcl_u32 width, height;                  /* texels; 0 × 0: no sky */
    pcl_u32 rowCdfOffset, columnCdfOffset;  /* floats into data[] */
    pcl_f32 cosRot, sinRot;                 /* the sky's rotation about +y */
    pcl_f32 integral;                       /* I = ∫ Y(L) dω over the sphere (4π L for a constant grey sky) */
    pcl_f32 pad0;
} PclEnvironment;
PCL_STATIC_ASSERT(sizeof(PclEnvironment) == 32, PclEnvironment_size);

/* The luminance Y of radiance L[3], by which the sky is sampled. */
PCL_INLINE pcl_f32 env_luminance(const pcl_f32 L[3]) { return 0.2126f * L[0] + 0.7152f * L[1] + 0.0722f * L[2]; }

PCL_INLINE int env_active(const PclEnvironment env) { return env.width > 0u && env.integral > 0.0f; }

/* The texel index y W + x of world direction w (unit, toward the sky). */
PCL_INLINE pcl_u32 env_texel_of(const PclEnvironment env, PclV3 w) {
    /* The sky turned by +α: a world direction turns back by −α into the map's frame. */
    const pcl_f32 lx = env.cosRot * w.x - env.sinRot * w.z;
    const pcl_f32 ly = w.y;
    const pcl_f32 lz = env.sinRot * w.x + env.cosRot * w.z;
    pcl_f32 u = PCL_ATAN2F(lx, -lz) / PCL_TWO_PI_F;
    if (u < 0.0f) u = u + 1.0f;
    const pcl_f32 cy = ly < -1.0f ? -1.0f : (ly > 1.0f ? 1.0f : ly);
    const pcl_f32 v = PCL_ACOSF(cy) / PCL_PI_F;
    pcl_i32 x = (pcl_i32)(u * (pcl_f32)env.width), y = (pcl_i32)(v * (pcl_f32)env.height);
    x = x < 0 ? 0 : (x >= (pcl_i32)env.width ? (pcl_i32)env.width - 1 : x);
    y = y < 0 ? 0 : (y >= (pcl_i32)env.height ? (pcl_i32)env.height - 1 : y);
    return (pcl_u32)y * env.width + (pcl_u32)x;
}

/* Radiance L[3] of texel t. */
PCL_INLINE void env_texel_radiance(PCL_GLOBAL const pcl_f32* data, pcl_u32 t, pcl_f32 L[3]) {
    L[0] = data[3u * t];
    L[1] = data[3u * t + 1u];
    L[2] = data[3u * t + 2u];
}

/* Radiance L[3] arriving from world direction w, and its sampling density p(w) (returned). */
PCL_INLINE pcl_f32 env_radiance(const PclEnvironment env, PCL_GLOBAL const pcl_f32* data, PclV3 w, pcl_f32 L[3]) {
    if (!env_active(env)) {
        L[0] = L[1] = L[2] = 0.0f;
        return 0.0f;
    }
    env_texel_radiance(data, env_texel_of(env, w), L);
    return env_luminance(L) / env.integral;
}

/* The solid-angle density env_sample gives world direction w. */
PCL_INLINE pcl_f32 env_pdf(const PclEnvironment env, PCL_GLOBAL const pcl_f32* data, PclV3 w) {
    pcl_f32 L[3];
    return env_radiance(env, data, w, L);
}

/* The last interval i in [0, n − 1) with cdf[i] <= u (cdf[0] = 0, increasing), skipping back over
 * empty intervals so a sample never lands where the density is 0. */
PCL_INLINE pcl_u32 env_find_interval(PCL_GLOBAL const pcl_f32* cdf, pcl_u32 n, pcl_f32 u) {
    pcl_u32 lo = 0u, hi = n - 2u;
    while (lo < hi) {
        const pcl_u32 mid = lo + (hi - lo + 1u) / 2u;
        if (cdf[mid] <= u)
            lo = mid;
        else
            hi = mid - 1u;
    }
    while (lo > 0u && !(cdf[lo + 1u] > cdf[lo])) --lo;
    return lo;
}

/* A direction *w toward the sky from (u1, u2), its density (returned; 0: no sample) and the
 * radiance L[3] from it (the sampled texel's). */
PCL_INLINE pcl_f32 env_sample(const PclEnvironment env, PCL_GLOBAL const pcl_f32* data, pcl_f32 u1, pcl_f32 u2,
                              PclV3* w, pcl_f32 L[3]) {
    L[0] = L[1] = L[2] = 0.0f;
    *w = sampling_v3(0.0f, 1.0f, 0.0f);
    if (!env_active(env)) return 0.0f;
    const pcl_u32 W = env.width, H = env.height;
    PCL_GLOBAL const pcl_f32* rowCdf = data + env.rowCdfOffset;
    const pcl_u32 y = env_find_interval(rowCdf, H + 1u, u1);
    const pcl_f32 r0 = rowCdf[y], r1 = rowCdf[y + 1u];
    pcl_f32 s1 = r1 > r0 ? (u1 - r0) / (r1 - r0) : 0.5f;
    s1 = s1 < 0.0f ? 0.0f : (s1 > 1.0f ? 1.0f : s1);
    PCL_GLOBAL const pcl_f32* cdf = data + env.columnCdfOffset + y * (W + 1u);
    const pcl_u32 x = env_find_interval(cdf, W + 1u, u2);
    const pcl_f32 c0 = cdf[x], c1 = cdf[x + 1u];
    pcl_f32 s2 = c1 > c0 ? (u2 - c0) / (c1 - c0) : 0.5f;
    s2 = s2 < 0.0f ? 0.0f : (s2 > 1.0f ? 1.0f : s2);
    /* Uniform in the texel's solid angle: φ over its columns, cos θ over its row. */
    const pcl_f32 phi = PCL_TWO_PI_F * ((pcl_f32)x + s2) / (pcl_f32)W;
    const pcl_f32 cos0 = PCL_COSF(PCL_PI_F * (pcl_f32)y / (pcl_f32)H);
    const pcl_f32 cos1 = PCL_COSF(PCL_PI_F * (pcl_f32)(y + 1u) / (pcl_f32)H);
    const pcl_f32 cosTheta = cos0 + s1 * (cos1 - cos0);
    const pcl_f32 s2t = 1.0f - cosTheta * cosTheta;
    const pcl_f32 sinTheta = s2t > 0.0f ? PCL_SQRTF(s2t) : 0.0f;
    pcl_f32 sinPhi, cosPhi;
    PCL_SINCOSF(phi, &sinPhi, &cosPhi);
    /* u = atan2(w.x, −w.z)/2π: local w = (sin θ sin φ, cos θ, −sin θ cos φ), then turned by +α. */
    const pcl_f32 lx = sinTheta * sinPhi, lz = -sinTheta * cosPhi;
    *w = sampling_v3(env.cosRot * lx + env.sinRot * lz, cosTheta, -env.sinRot * lx + env.cosRot * lz);
    env_texel_radiance(data, y * W + x, L);
    return env_luminance(L) / env.integral;
}

#endif /* PCL_ENVIRONMENT_H */
