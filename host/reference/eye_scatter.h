// What the eye-pass twins share (kernels/README.md, "Eye pass"): the surface normal at a hit,
// the diffuse/specular lobe choice of a mixed surface, specular scattering and the MIS weight,
// written from the README with the reference BSDF's helpers.
#pragma once
#include <cmath>
#include <cstdint>

#include "prep/scene_buffers.h"
#include "reference/bsdf.h"
#include "reference/sampling.h"
#include "shared/shading_frame.h"
#include "shared/types.h"

namespace pcl {

inline Vec3 eyeVec(const float v[4]) { return {v[0], v[1], v[2]}; }

// The unit outside normal of `prim` at p, spheres at shutter time tau.
inline Vec3 eyeNormalAt(const SceneBuffers& b, uint32_t prim, uint32_t triangleCount, Vec3 p, float tau) {
    const PclPrimInfo& info = b.primInfo[prim];
    if (prim >= triangleCount) {
        const Vec3 c(info.a + info.mx * tau, info.b + info.my * tau, info.c + info.mz * tau);
        return Vec3((p.x - c.x) / info.radius, (p.y - c.y) / info.radius, (p.z - c.z) / info.radius);
    }
    return {info.a, info.b, info.c};
}

// The shading normal of a hit (on n's side; n where there is none) by the kernels' own lookup
// (kernels/shared/shading_frame.h), from the buffers' per-triangle normals and normal maps
// (empty: none).
inline Vec3 eyeShadingNormal(const SceneBuffers& b, uint32_t triangleCount, const PclHit& hit, Vec3 n) {
    const bool mapped = b.normalMaps.mapped();
    if (b.triangleNormals.empty() && !mapped) return n;
    const PclV3 s = shading_normal(b.triangleNormals.empty() ? nullptr : b.triangleNormals.data(),
                                   mapped ? b.normalMaps.triangleTangents.data() : nullptr,
                                   mapped ? b.normalMaps.maps.data() : nullptr, b.textures.texels.data(),
                                   b.textures.triangleUvs.data(), b.primInfo[hit.prim].material, hit.prim,
                                   triangleCount, hit.u, hit.v, sampling_v3(n.x, n.y, n.z));
    return {s.x, s.y, s.z};
}

// shading_is_smooth (the kernels' rule) on host vectors.
inline bool eyeIsSmooth(Vec3 ns, Vec3 n) {
    return shading_is_smooth(sampling_v3(ns.x, ns.y, ns.z), sampling_v3(n.x, n.y, n.z));
}

// P_d = lum(ρd) / (lum(ρd) + lum(ρs)); negative for a black surface.
inline float eyeDiffuseProbability(const PclMaterial& m) {
    const float ld = luminance(eyeVec(m.rhoD));
    const float ls = m.specular != PCL_SPECULAR_NONE ? luminance(eyeVec(m.rhoS)) : 0.0f;
    const float sum = ld + ls;
    return sum > 0.0f ? ld / sum : -1.0f;
}

// The specular part scatters unit d (arriving at outside normal n, shading normal ns on n's
// side, = n on flat surfaces); weight before 1/P_s (refraction: ρs η², η = η_i/η_t on the
// path's side over the other). Where ns differs from n a reflection must stay on d's side of
// the geometric surface and a refraction cross it.
inline bool eyeSpecularScatter(const PclMaterial& m, Vec3 d, Vec3 n, Vec3 ns, float uF, float uA, float uB, Vec3& dNew,
                               Vec3& weight) {
    const float dn = dot(d, n);
    const Vec3 nf = dn < 0.0f ? ns : -ns;  // the shading normal on the path's side
    weight = eyeVec(m.rhoS);
    const Vec3 mirror = d - nf * (2.0f * dot(d, nf));
    bool crosses = false;
    switch (m.specular) {
        case PCL_SPECULAR_MIRROR: dNew = mirror; break;
        case PCL_SPECULAR_GLOSSY: {
            dNew = samplePhongLobe(mirror, m.exponent, uA, uB);
            const float cosOut = dot(dNew, nf);
            if (!(cosOut > 0.0f)) return false;
            weight = weight * ((m.exponent + 2.0f) / (m.exponent + 1.0f) * cosOut);
            break;
        }
        case PCL_SPECULAR_DIELECTRIC: {
            const bool entering = dn < 0.0f;
            const float eta = entering ? 1.0f / m.ior : m.ior;
            const float cosI = std::fabs(dot(d, ns));
            const float F = entering ? fresnelDielectric(cosI, 1.0f, m.ior) : fresnelDielectric(cosI, m.ior, 1.0f);
            if (uF < F) {
                dNew = mirror;
            } else {
                const float cosT = std::sqrt(std::max(0.0f, 1.0f - eta * eta * (1.0f - cosI * cosI)));
                dNew = d * eta + nf * (eta * cosI - cosT);
                weight = weight * (eta * eta);  // radiance scales by (η_i/η_t)² across the surface
                crosses = true;
            }
            break;
        }
        default: return false;
    }
    if (eyeIsSmooth(ns, n)) {
        const float side = dot(dNew, n) * dn;  // < 0: back to d's side
        if (crosses ? !(side > 0.0f) : !(side < 0.0f)) return false;
    }
    return true;
}

// The normalised Phong lobe of exponent e at a hit reached along d (facing normal nf), toward
// wi: cos^e α about reflect(d, nf); 0 below the surface or outside the lobe. BRDF ρs (e+2)/(2π)
// times it, the lobe's sampling density (e+1)/(2π) times it.
inline float eyePhongCosPower(Vec3 d, Vec3 nf, Vec3 wi, float e) {
    if (!(dot(wi, nf) > 0.0f)) return 0.0f;
    const float k = 2.0f * dot(d, nf);
    const float cosA = dot(wi, Vec3(d.x - k * nf.x, d.y - k * nf.y, d.z - k * nf.z));
    return cosA > 0.0f ? std::pow(cosA, e) : 0.0f;
}

// Power heuristic with counts: (nA pA)² / ((nA pA)² + (nB pB)²), 0 when both are 0.
inline float eyeMisWeight(uint32_t nA, float pA, uint32_t nB, float pB) {
    const float a = float(nA) * pA, b = float(nB) * pB;
    const float a2 = a * a, s = a2 + b * b;
    return s > 0.0f ? a2 / s : 0.0f;
}

// Solid-angle density of direct_light's area sampling for point at squared distance d2 along
// unit wi on triangle light L: (s_L / S) d² / (A cosθ_L); 0 from behind.
inline float eyeAreaLightPdf(const PclLight& L, float areaPowerTotal, Vec3 wi, float d2) {
    const float cosL = -dot(eyeVec(L.axis), wi);
    if (!(cosL > 0.0f) || !(areaPowerTotal > 0.0f)) return 0.0f;
    const float s = (L.power[0] + L.power[1] + L.power[2]) / 3.0f;
    return (s / areaPowerTotal) * d2 / (L.area * cosL);
}

// Importance histograms of the gather (kernels/README.md, "final gather"): the cell of unit
// direction w above n on the cosine map's G × G square, through the inverse concentric map.
inline uint32_t eyeCellOfDirection(Vec3 n, Vec3 w, uint32_t G) {
    Vec3 t, b;
    makeBasis(n, t, b);
    const float x = dot(w, t), y = dot(w, b);
    const float r = std::sqrt(x * x + y * y);
    float a = 0.0f, c = 0.0f;
    if (r == 0.0f) {
    } else if (std::fabs(x) > std::fabs(y)) {
        a = x > 0.0f ? r : -r;
        c = a * (4.0f / kPi) * std::atan2(y / a, x / a);
    } else {
        c = y > 0.0f ? r : -r;
        a = c * (4.0f / kPi) * (kPi / 2.0f - std::atan2(y / c, x / c));
    }
    const float s1 = 0.5f * (a + 1.0f), s2 = 0.5f * (c + 1.0f);
    const int cx = std::min(std::max(int(std::floor(s1 * float(G))), 0), int(G) - 1);
    const int cy = std::min(std::max(int(std::floor(s2 * float(G))), 0), int(G) - 1);
    return uint32_t(cy) * G + uint32_t(cx);
}
inline float eyeCellProbability(const float* cdf, uint32_t c) { return c == 0 ? cdf[0] : cdf[c] - cdf[c - 1]; }

inline PclRay eyeRay(Vec3 o, Vec3 d, float tmax, float time) {
    PclRay r{};
    r.ox = o.x;
    r.oy = o.y;
    r.oz = o.z;
    r.tmin = 0.0f;
    r.dx = d.x;
    r.dy = d.y;
    r.dz = d.z;
    r.tmax = tmax;
    r.time = time;
    return r;
}

}  // namespace pcl
