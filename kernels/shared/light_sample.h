/* light_sample.h: next-event estimation at a shading point (delta, triangle and sky lights),
 * shared by direct_light (at the diffuse eye record, BRDF ρd/π), eye_paths (at glossy chain hits,
 * the Phong lobe; the single scattering along medium segments) and final_gather (the direct light
 * at close gather hits): the light's incident contribution before the BRDF.
 * In a scene with media (EyeMedia.hasMedia) the shadow rays carry the transmittance of media and
 * invisible boundaries (shared/eye_medium.h); without, they are the plain visibility tests, and
 * the transmittance 1 they report leaves every product bit-identical. Rules: kernels/README.md,
 * "direct light". */
#ifndef PCL_LIGHT_SAMPLE_H
#define PCL_LIGHT_SAMPLE_H
#ifdef __OPENCL_VERSION__

#include "types.h"
#include "sampling.h"
#include "bvh.h"
#include "eye.h"
#include "eye_medium.h"
#include "environment.h"

/* shared/texture.h's lookup, declared here and defined there: the kernels include texture.h
 * after this header, so its `FP_CONTRACT OFF` pragma leaves the functions above and here
 * compiled as they were before emission textures (bit-identical images). */
inline void texture_emission_at(__global const PclMaterialTextures* materialTextures, __global const float* texels,
                                __global const PclTriangleUv* triangleUvs, uint material, uint prim, uint triangleCount,
                                float bu, float bv, const float emission[4], float le[3]);

/* What a triangle light's radiance at a point needs beyond its material's constant: the
 * emission textures (shared/texture.h; placeholders, never read, without PCL_TEXTURED). */
typedef struct LightTextures {
    __global const PclMaterialTextures* materialTextures;
    __global const float* texels;
    __global const PclTriangleUv* triangleUvs;
    uint triangleCount;
} LightTextures;

inline LightTextures light_textures(__global const PclMaterialTextures* materialTextures, __global const float* texels,
                                    __global const PclTriangleUv* triangleUvs, uint triangleCount) {
    LightTextures t;
    t.materialTextures = materialTextures;
    t.texels = texels;
    t.triangleUvs = triangleUvs;
    t.triangleCount = triangleCount;
    return t;
}

/* The radiance triangle light L emits at barycentrics (bu, bv): its material's emission times
 * the emission texel there (texture_emission_at). */
inline void light_emission_at(const LightTextures lt, __global const PclPrimInfo* primInfo,
                              __global const PclMaterial* materials, const PclLight L, float bu, float bv, float le[3]) {
    const uint mat = primInfo[L.prim].material;
    const PclMaterial E = materials[mat];
    texture_emission_at(lt.materialTextures, lt.texels, lt.triangleUvs, mat, L.prim, lt.triangleCount, bu, bv,
                        E.emission, le);
}

/* Unoccluded segment from o (already lifted) to o + dir·t, t in (0, tmax). */
inline bool light_visible(__global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                          __global const PclSphere* spheres, PclV3 o, PclV3 dir, float tmax, float tau) {
    const PclRay r = bvh_ray(o.x, o.y, o.z, dir.x, dir.y, dir.z, 0.0f, tmax, tau);
    PclHit hit;
    return !bvh_trace(nodes, packets, spheres, r, true, &hit);
}

/* The shadow segment o + dir·t, t in (0, tmax), starting in `medium`: tr[3] its transmittance
 * (1 or 0 without media); false when nothing arrives. */
inline bool light_shadow(__global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                         __global const PclSphere* spheres, const EyeMedia em, int medium, PclV3 o, PclV3 dir,
                         float tmax, float tau, float tr[3]) {
    if (em.hasMedia)
        return eye_shadow_transmittance(nodes, packets, spheres, em, medium, o, dir, tmax, tau, tr);
    const bool visible = light_visible(nodes, packets, spheres, o, dir, tmax, tau);
    tr[0] = tr[1] = tr[2] = visible ? 1.0f : 0.0f;
    return visible;
}

inline float light_smoothstep(float e0, float e1, float x) {
    if (e1 <= e0) return x >= e1 ? 1.0f : 0.0f;
    float t = (x - e0) / (e1 - e0);
    t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
    return t * t * (3.0f - 2.0f * t);
}

/* I/Φ of a point or spot light L toward a receiver that sees it in the unit direction wi:
 * 1/(4π), or the spot's fall-off over its normaliser (0 outside the cone). */
inline float light_intensity_scale(const PclLight L, PclV3 wi) {
    if (L.type == PCL_LIGHT_POINT) return 1.0f / (4.0f * PCL_PI_F);
    const float cosAxis = -(L.axis[0] * wi.x + L.axis[1] * wi.y + L.axis[2] * wi.z);
    const float falloff = light_smoothstep(L.cosOuter, L.cosInner, cosAxis);
    if (!(falloff > 0.0f)) return 0.0f;
    return falloff / (2.0f * PCL_PI_F * ((1.0f - L.cosInner) + 0.5f * (L.cosInner - L.cosOuter)));
}

/* A point, spot or directional light L seen from p (facing geometric normal nf, facing shading
 * normal sf: the side test by nf, the cosine by sf; o = p lifted; the shadow ray starts in
 * `medium`): the unit direction *wi to it, the shadow ray's transmittance tr[3]
 * and the factor g with contribution Φ ⊙ g ⊙ tr (times the BRDF): cosθ/(πR²) (directional),
 * I/Φ · cosθ/d² (point, spot with its fall-off); 0 when unlit or occluded. */
inline float light_delta(__global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                         __global const PclSphere* spheres, const EyeMedia em, int medium, const PclLight L, PclV3 p,
                         PclV3 nf, PclV3 sf, PclV3 o, float tau, PclV3* wi, float tr[3]) {
    if (L.type == PCL_LIGHT_DIRECTIONAL) {
        *wi = sampling_v3(-L.axis[0], -L.axis[1], -L.axis[2]);
        const float cosS = sampling_dot(sf, *wi);
        if (!(cosS > 0.0f) || !(sampling_dot(nf, *wi) > 0.0f)) return 0.0f;
        if (!light_shadow(nodes, packets, spheres, em, medium, o, *wi, INFINITY, tau, tr)) return 0.0f;
        return cosS / (PCL_PI_F * L.radius * L.radius);  /* E = Φ / (π R²) */
    }
    const PclV3 toL = sampling_v3(L.p[0] - p.x, L.p[1] - p.y, L.p[2] - p.z);
    const float d2 = sampling_dot(toL, toL);
    if (!(d2 > 0.0f)) return 0.0f;
    const float dist = sqrt(d2);
    *wi = sampling_v3(toL.x / dist, toL.y / dist, toL.z / dist);
    const float cosS = sampling_dot(sf, *wi);
    if (!(cosS > 0.0f) || !(sampling_dot(nf, *wi) > 0.0f)) return 0.0f;
    const float scale = light_intensity_scale(L, *wi); /* I / Φ × falloff */
    if (!(scale > 0.0f)) return 0.0f;
    const PclV3 seg = sampling_v3(L.p[0] - o.x, L.p[1] - o.y, L.p[2] - o.z);
    if (!light_shadow(nodes, packets, spheres, em, medium, o, seg, 1.0f, tau, tr)) return 0.0f;
    return scale * cosS / d2;
}

/* Every point, spot and directional light of lights[0 .. lightCount) seen from p (light_delta):
 * E[c] += Φ_c g tr_c, in light order (the irradiance the BRDF then weighs). */
inline void light_delta_irradiance(__global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                                   __global const PclSphere* spheres, const EyeMedia em, int medium,
                                   __global const PclLight* lights, uint lightCount, PclV3 p, PclV3 nf, PclV3 sf,
                                   PclV3 o, float tau, float E[3]) {
    for (uint l = 0u; l < lightCount; ++l) {
        const PclLight L = lights[l];
        if (L.type == PCL_LIGHT_TRIANGLE || L.type == PCL_LIGHT_ENVIRONMENT) continue;
        PclV3 wi;
        float tr[3];
        const float g = light_delta(nodes, packets, spheres, em, medium, L, p, nf, sf, o, tau, &wi, tr);
        if (!(g > 0.0f)) continue;
        for (int c = 0; c < 3; ++c) E[c] = E[c] + L.power[c] * g * tr[c];
    }
}

/* Triangle light choice and point: u0 chooses the light (the first l with u0 < areaCdf[l]),
 * (u1, u2) a point *q uniform in its area (at shutter time tau), at barycentrics (*bu, *bv)
 * (q = p0 + bu e1 + bv e2); false when the entry chosen is not a triangle light. */
inline bool light_area_point(__global const PclLight* lights, __global const float* areaCdf, uint lightCount,
                             float tau, float u0, float u1, float u2, PclLight* chosen, PclV3* q, float* bu,
                             float* bv) {
    uint l = 0u;
    while (l + 1u < lightCount && !(u0 < areaCdf[l])) ++l;
    const PclLight L = lights[l];
    if (L.type != PCL_LIGHT_TRIANGLE) return false;
    float b0, b1;
    sampling_uniform_triangle(u1, u2, &b0, &b1);
    const float b2 = 1.0f - b0 - b1;
    *q = sampling_v3(L.p[0] + L.e1[0] * b1 + L.e2[0] * b2 + L.motion[0] * tau,
                     L.p[1] + L.e1[1] * b1 + L.e2[1] * b2 + L.motion[1] * tau,
                     L.p[2] + L.e1[2] * b1 + L.e2[2] * b2 + L.motion[2] * tau);
    *chosen = L;
    *bu = b1;
    *bv = b2;
    return true;
}

/* One triangle-light sample for p (light_area_point; facing normals nf and sf as for
 * light_delta): on success *wi, the solid-angle density *pdfL, cosθ to sf at p (*cosS) and the
 * light's radiance at the point (its emission texture's, if any) times the shadow ray's
 * transmittance le[3]
 * (the ray starts in `medium`); false when the sample is below the surface, on the light's back
 * or occluded. */
inline bool light_area_sample(__global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                              __global const PclSphere* spheres, const EyeMedia em, int medium,
                              __global const PclPrimInfo* primInfo, __global const PclMaterial* materials,
                              const LightTextures lt, __global const PclLight* lights, __global const float* areaCdf, uint lightCount,
                              float areaPowerTotal, PclV3 p, PclV3 nf, PclV3 sf, PclV3 o, float eps, float tau, float u0,
                              float u1, float u2, PclV3* wi, float* pdfL, float* cosS, float le[3]) {
    PclLight L;
    PclV3 q;
    float bu, bv;
    if (!light_area_point(lights, areaCdf, lightCount, tau, u0, u1, u2, &L, &q, &bu, &bv)) return false;
    const PclV3 toL = sampling_v3(q.x - p.x, q.y - p.y, q.z - p.z);
    const float d2 = sampling_dot(toL, toL);
    if (!(d2 > 0.0f)) return false;
    const float dist = sqrt(d2);
    *wi = sampling_v3(toL.x / dist, toL.y / dist, toL.z / dist);
    *cosS = sampling_dot(sf, *wi);
    if (!(*cosS > 0.0f) || !(sampling_dot(nf, *wi) > 0.0f)) return false;
    *pdfL = eye_area_light_pdf(L, areaPowerTotal, *wi, d2);
    if (!(*pdfL > 0.0f)) return false;
    const PclV3 end = sampling_v3(q.x + L.axis[0] * eps, q.y + L.axis[1] * eps, q.z + L.axis[2] * eps);
    const PclV3 seg = sampling_v3(end.x - o.x, end.y - o.y, end.z - o.z);
    float tr[3];
    if (!light_shadow(nodes, packets, spheres, em, medium, o, seg, 1.0f, tau, tr)) return false;
    float Le[3];
    light_emission_at(lt, primInfo, materials, L, bu, bv, Le);
    for (int c = 0; c < 3; ++c) le[c] = Le[c] * tr[c];
    return true;
}

/* One sample of the sky by its map (shared/environment.h) from (u0, u1), for the shading point
 * with normals nf (geometric, on the incident side) and sf (shading), its shadow ray from o in
 * `medium`: on success *wi, the density *pdfL, cosθ to sf (*cosS) and the sky's radiance times
 * the shadow ray's transmittance le[3]; false when the map gives the direction no density, it
 * lies below either normal, or the ray is blocked. */
inline bool light_sky_sample(__global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                             __global const PclSphere* spheres, const EyeMedia em, int medium, const PclEnvironment env,
                             __global const float* envData, PclV3 nf, PclV3 sf, PclV3 o, float tau, float u0, float u1,
                             PclV3* wi, float* pdfL, float* cosS, float le[3]) {
    float Lsky[3], tr[3];
    *pdfL = env_sample(env, envData, u0, u1, wi, Lsky);
    if (!(*pdfL > 0.0f)) return false;
    *cosS = sampling_dot(sf, *wi);
    if (!(*cosS > 0.0f) || !(sampling_dot(nf, *wi) > 0.0f)) return false;
    if (!light_shadow(nodes, packets, spheres, em, medium, o, *wi, INFINITY, tau, tr)) return false;
    for (int c = 0; c < 3; ++c) le[c] = Lsky[c] * tr[c];
    return true;
}

#endif /* __OPENCL_VERSION__ */
#endif /* PCL_LIGHT_SAMPLE_H */
