// Next-event estimation at a shading point (delta, triangle and sky lights), the twin of
// kernels/shared/light_sample.h: shared by the direct-light twin (the diffuse record, ρd/π), the
// eye-path twin (glossy chain hits, the Phong lobe, single scattering in media) and the final
// gather's twin (close gather hits). The light's incident contribution before the BRDF
// (kernels/README.md, "direct light"); shadow rays carry the transmittance of media.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/scene_geometry.h"
#include "prep/area_light_table.h"
#include "prep/scene_buffers.h"
#include "reference/eye_medium.h"
#include "reference/eye_scatter.h"
#include "reference/sampling.h"
#include "reference/sky.h"
#include "shared/texture.h"

namespace pcl {

// Where a shadow ray starts and how it is traced: in `medium`, through media and invisible
// boundaries when hasMedia (reference/eye_medium.h), else a plain occlusion test.
struct ShadowMedium {
    bool hasMedia = false;
    int32_t medium = PCL_NO_MEDIUM;
};

// I/Φ of a point or spot light seen from a receiver in the unit direction wi: 1/(4π), or the
// spot's fall-off over its normaliser (0 outside the cone).
inline float lightIntensityScale(const PclLight& L, Vec3 wi) {
    if (L.type == PCL_LIGHT_POINT) return 1.0f / (4.0f * kPi);
    const float falloff = smoothstep(L.cosOuter, L.cosInner, -dot(eyeVec(L.axis), wi));
    if (!(falloff > 0.0f)) return 0.0f;
    return falloff / (2.0f * kPi * ((1.0f - L.cosInner) + 0.5f * (L.cosInner - L.cosOuter)));
}

// A point, spot or directional light seen from p (facing geometric normal nf for the side
// test, facing shading normal sf for the cosine; o = p lifted): wi, the
// shadow ray's transmittance tr and the factor g with contribution Φ g tr (times the BRDF); 0
// when unlit or occluded.
inline float lightDelta(const SceneGeometry& geometry, const SceneBuffers& buffers, ShadowMedium sm, const PclLight& L,
                        Vec3 p, Vec3 nf, Vec3 sf, Vec3 o, float tau, Vec3& wi, Vec3& tr) {
    if (L.type == PCL_LIGHT_DIRECTIONAL) {
        wi = -eyeVec(L.axis);
        const float cosS = dot(sf, wi);
        if (!(cosS > 0.0f) || !(dot(nf, wi) > 0.0f)) return 0.0f;
        tr = eyeShadowTransmittance(geometry, buffers, sm.hasMedia, sm.medium, o, wi,
                                    std::numeric_limits<float>::infinity(), tau);
        if (!(maxComponent(tr) > 0.0f)) return 0.0f;
        return cosS / (kPi * L.radius * L.radius);  // E = Φ/(πR²), × cosθ
    }
    const Vec3 toL = eyeVec(L.p) - p;
    const float d2 = dot(toL, toL);
    if (!(d2 > 0.0f)) return 0.0f;
    const float dist = std::sqrt(d2);
    wi = Vec3(toL.x / dist, toL.y / dist, toL.z / dist);
    const float cosS = dot(sf, wi);
    if (!(cosS > 0.0f) || !(dot(nf, wi) > 0.0f)) return 0.0f;
    const float scale = lightIntensityScale(L, wi);  // I/Φ with the spot's falloff
    if (!(scale > 0.0f)) return 0.0f;
    tr = eyeShadowTransmittance(geometry, buffers, sm.hasMedia, sm.medium, o, eyeVec(L.p) - o, 1.0f, tau);
    if (!(maxComponent(tr) > 0.0f)) return 0.0f;
    return scale * cosS / d2;
}

// Every point, spot and directional light of the first lightCount seen from p (lightDelta):
// Σ Φ g tr in light order (shared/light_sample.h, light_delta_irradiance), added to E.
inline Vec3 lightDeltaIrradiance(const SceneGeometry& geometry, const SceneBuffers& buffers, ShadowMedium sm,
                                 uint32_t lightCount, Vec3 p, Vec3 nf, Vec3 sf, Vec3 o, float tau, Vec3 E) {
    for (uint32_t l = 0; l < lightCount; ++l) {
        const PclLight& L = buffers.lights[l];
        if (L.type == PCL_LIGHT_TRIANGLE || L.type == PCL_LIGHT_ENVIRONMENT) continue;
        Vec3 wi, tr;
        const float g = lightDelta(geometry, buffers, sm, L, p, nf, sf, o, tau, wi, tr);
        if (g > 0.0f) E = E + eyeVec(L.power) * g * tr;
    }
    return E;
}

// The radiance triangle light L emits at barycentrics (bu, bv): its material's emission times
// its emission texel there (shared/texture.h's lookup on the same buffers).
inline Vec3 lightEmissionAt(const SceneBuffers& buffers, uint32_t triangleCount, const PclLight& L, float bu,
                            float bv) {
    const uint32_t mat = buffers.primInfo[L.prim].material;
    const PclMaterial& E = buffers.materials[mat];
    if (mat >= buffers.textures.materialTextures.size()) return eyeVec(E.emission);  // made without textures
    float le[3];
    texture_emission_at(buffers.textures.materialTextures.data(), buffers.textures.texels.data(),
                        buffers.textures.triangleUvs.data(), mat, L.prim, triangleCount, bu, bv, E.emission, le);
    return Vec3(le[0], le[1], le[2]);
}

// Triangle light choice and point: u0 chooses the light (the table's cdf), (u1, u2) a point q
// uniform in its area at shutter time tau, at barycentrics (bu, bv) (q = p0 + bu e1 + bv e2);
// false when the entry chosen is not a triangle light.
inline bool lightAreaPoint(const SceneBuffers& buffers, const AreaLightTable& table, uint32_t lightCount, float tau,
                           float u0, float u1, float u2, const PclLight*& chosen, Vec3& q, float& bu, float& bv) {
    // The first light whose cumulative probability exceeds u0.
    const size_t l =
        std::min<size_t>(std::upper_bound(table.cdf.begin(), table.cdf.end(), u0) - table.cdf.begin(), lightCount - 1);
    const PclLight& L = buffers.lights[l];
    if (L.type != PCL_LIGHT_TRIANGLE) return false;
    float b0, b1;
    sampleUniformTriangle(u1, u2, b0, b1);
    const float b2 = 1.0f - b0 - b1;
    q = eyeVec(L.p) + eyeVec(L.e1) * b1 + eyeVec(L.e2) * b2 + eyeVec(L.motion) * tau;
    chosen = &L;
    bu = b1;
    bv = b2;
    return true;
}

// One triangle-light sample (lightAreaPoint; nf, sf as for lightDelta). On success wi, the
// solid-angle density pdfL, cosθ to sf at p and the light's radiance at the point (its emission
// texture's, if any) times the shadow ray's transmittance, le.
inline bool lightAreaSample(const SceneGeometry& geometry, const SceneBuffers& buffers, const AreaLightTable& table,
                            ShadowMedium sm, uint32_t lightCount, float areaPowerTotal, Vec3 p, Vec3 nf, Vec3 sf,
                            Vec3 o, float eps, float tau, float u0, float u1, float u2, Vec3& wi, float& pdfL,
                            float& cosS, Vec3& le) {
    const PclLight* chosen = nullptr;
    Vec3 q;
    float bu, bv;
    if (!lightAreaPoint(buffers, table, lightCount, tau, u0, u1, u2, chosen, q, bu, bv)) return false;
    const PclLight& L = *chosen;
    const Vec3 toL = q - p;
    const float d2 = dot(toL, toL);
    if (!(d2 > 0.0f)) return false;
    const float dist = std::sqrt(d2);
    wi = Vec3(toL.x / dist, toL.y / dist, toL.z / dist);
    cosS = dot(sf, wi);
    if (!(cosS > 0.0f) || !(dot(nf, wi) > 0.0f)) return false;
    pdfL = eyeAreaLightPdf(L, areaPowerTotal, wi, d2);
    if (!(pdfL > 0.0f)) return false;
    const Vec3 end = q + eyeVec(L.axis) * eps;
    const Vec3 tr = eyeShadowTransmittance(geometry, buffers, sm.hasMedia, sm.medium, o, end - o, 1.0f, tau);
    if (!(maxComponent(tr) > 0.0f)) return false;
    le = lightEmissionAt(buffers, geometry.triangleCount(), L, bu, bv) * tr;
    return true;
}

// One sample of the sky by its map from (u0, u1) (nf, sf as for lightAreaSample; shadow ray from
// o in sm's medium): on success wi, the density pdfL, cosθ to sf and the sky's radiance times the
// shadow ray's transmittance, le.
inline bool lightSkySample(const SceneGeometry& geometry, const SceneBuffers& buffers, ShadowMedium sm, Vec3 nf,
                           Vec3 sf, Vec3 o, float tau, float u0, float u1, Vec3& wi, float& pdfL, float& cosS,
                           Vec3& le) {
    Vec3 Lsky;
    pdfL = skySample(buffers, u0, u1, wi, Lsky);
    if (!(pdfL > 0.0f)) return false;
    cosS = dot(sf, wi);
    if (!(cosS > 0.0f) || !(dot(nf, wi) > 0.0f)) return false;
    const Vec3 tr = eyeShadowTransmittance(geometry, buffers, sm.hasMedia, sm.medium, o, wi,
                                           std::numeric_limits<float>::infinity(), tau);
    if (!(maxComponent(tr) > 0.0f)) return false;
    le = Lsky * tr;
    return true;
}

}  // namespace pcl
