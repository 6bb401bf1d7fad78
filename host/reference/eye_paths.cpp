#include "reference/eye_paths.h"

#include <cmath>
#include <limits>

#include "reference/eye_medium.h"
#include "reference/eye_scatter.h"
#include "reference/light_sample.h"
#include "reference/medium.h"
#include "reference/parallel_for.h"
#include "reference/sampler.h"
#include "reference/sky.h"
#include "reference/textured_material.h"

namespace pcl {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// Single scattering along o + t d, t ∈ [0, tEnd] (+∞ when the ray leaves the scene), in medium
// `medium`, before the path throughput (kernels/README.md, "Eye pass: media"): per delta light
// one distance (equiangular toward point and spot lights, exponential in the channels' mean σt
// for directional ones), one triangle-light sample with an equiangular distance toward its
// point; Σ Tr(t) σs p(d·wi) Li tr_shadow / pdf(t).
Vec3 singleScatter(const SceneGeometry& geometry, const SceneBuffers& buffers, const AreaLightTable& table,
                   const PclEyeParams& params, int32_t medium, Vec3 o, Vec3 d, float tEnd, float tau, uint64_t seed,
                   uint32_t pixel, uint32_t k, uint32_t segment) {
    const PclMedium& m = buffers.media[size_t(medium)];
    const Vec3 sigmaS = eyeVec(m.sigmaS);
    Vec3 Ls(0.0f);
    const uint32_t base = segment * (params.lightCount + 1);
    for (uint32_t l = 0; l < params.lightCount; ++l) {
        const PclLight& L = buffers.lights[l];
        if (L.type == PCL_LIGHT_TRIANGLE || L.type == PCL_LIGHT_ENVIRONMENT) continue;
        uint32_t w[4];
        rng_block(seed, pixel, k, base + 1 + l, PCL_RNG_STREAM_EYE_MEDIUM, w);
        const float u = rng_u01(w[0]);
        float t, pdf, scale;
        Vec3 wi, tr;
        if (L.type == PCL_LIGHT_DIRECTIONAL) {
            const float sbar =
                ((m.sigmaA[0] + m.sigmaS[0]) + (m.sigmaA[1] + m.sigmaS[1]) + (m.sigmaA[2] + m.sigmaS[2])) / 3.0f;
            if (!(sbar > 0.0f)) continue;
            const float mass = tEnd < kInfinity ? -std::expm1(-sbar * tEnd) : 1.0f;  // P(t ≤ tEnd)
            if (!(mass > 0.0f)) continue;
            t = std::min(-std::log1p(-u * mass) / sbar, tEnd);
            pdf = sbar * std::exp(-sbar * t) / mass;
            if (!(pdf > 0.0f)) continue;
            wi = -eyeVec(L.axis);
            tr = eyeShadowTransmittance(geometry, buffers, true, medium, o + d * t, wi, kInfinity, tau);
            if (!(maxComponent(tr) > 0.0f)) continue;
            scale = 1.0f / (kPi * L.radius * L.radius);  // E = Φ/(πR²)
        } else {
            const Vec3 c = eyeVec(L.p);
            if (!eyeEquiangular(o, d, c, tEnd, u, t, pdf)) continue;
            const Vec3 x = o + d * t;
            const Vec3 toL = c - x;
            const float d2 = dot(toL, toL);
            if (!(d2 > 0.0f)) continue;
            const float dist = std::sqrt(d2);
            wi = Vec3(toL.x / dist, toL.y / dist, toL.z / dist);
            scale = lightIntensityScale(L, wi) / d2;  // I/(Φ d²)
            if (!(scale > 0.0f)) continue;
            tr = eyeShadowTransmittance(geometry, buffers, true, medium, x, toL, 1.0f, tau);
            if (!(maxComponent(tr) > 0.0f)) continue;
        }
        const float f = henyeyGreenstein(dot(d, wi), m.g) * scale / pdf;
        Ls = Ls + eyeMediumTransmittance(m, t) * sigmaS * eyeVec(L.power) * tr * Vec3(f);
    }
    if (!(params.areaPowerTotal > 0.0f)) return Ls;
    uint32_t w[4];
    rng_block(seed, pixel, k, base, PCL_RNG_STREAM_EYE_MEDIUM, w);
    const PclLight* chosen = nullptr;
    Vec3 q;
    float bu, bv;
    if (!lightAreaPoint(buffers, table, params.lightCount, tau, rng_u01(w[0]), rng_u01(w[1]), rng_u01(w[2]), chosen, q,
                        bu, bv))
        return Ls;
    const PclLight& L = *chosen;
    float t, pdf;
    if (!eyeEquiangular(o, d, q, tEnd, rng_u01(w[3]), t, pdf)) return Ls;
    const Vec3 x = o + d * t;
    const Vec3 toL = q - x;
    const float d2 = dot(toL, toL);
    if (!(d2 > 0.0f)) return Ls;
    const float dist = std::sqrt(d2);
    const Vec3 wi(toL.x / dist, toL.y / dist, toL.z / dist);
    const float pdfL = eyeAreaLightPdf(L, params.areaPowerTotal, wi, d2);
    if (!(pdfL > 0.0f)) return Ls;
    const Vec3 end = q + eyeVec(L.axis) * params.rayEpsilon;
    const Vec3 tr = eyeShadowTransmittance(geometry, buffers, true, medium, x, end - x, 1.0f, tau);
    if (!(maxComponent(tr) > 0.0f)) return Ls;
    const Vec3 le = lightEmissionAt(buffers, geometry.triangleCount(), L, bu, bv);
    const float f = henyeyGreenstein(dot(d, wi), m.g) / (pdfL * pdf);
    return Ls + eyeMediumTransmittance(m, t) * sigmaS * le * tr * Vec3(f);
}

}  // namespace

PclEyeHit referenceEyePath(const SceneGeometry& geometry, const SceneBuffers& buffers, const AreaLightTable& table,
                           const PclEyeParams& params, const PclRay& ray, uint32_t i,
                           std::vector<PclVolumeSegment>* segments) {
    const uint32_t s = params.firstSample + i;
    const uint32_t pixel = s / params.samplesPerPixel, k = s % params.samplesPerPixel;
    const uint64_t seed = uint64_t(params.seedLo) | uint64_t(params.seedHi) << 32;
    Sampler sampler(seed, pixel, k);
    PclEyeHit h{};
    h.time = ray.time;
    h.prim = PCL_NO_HIT;
    h.pixel = pixel;
    h.sample = k;
    Vec3 o(ray.ox, ray.oy, ray.oz), d(ray.dx, ray.dy, ray.dz);
    Vec3 T(1.0f), Le(0.0f);
    float pdfLobe = 0.0f;  // the density with which the last hit's glossy lobe chose d; 0 if not glossy
    const bool hasMedia = params.volumeSegments > 0;
    int32_t medium = hasMedia ? params.cameraMedium : PCL_NO_MEDIUM;
    std::vector<PclVolumeSegment> recorded;
    uint32_t crossings = 0;
    float travelled = 0.0f;  // media: distance from the last hit to the invisible boundary crossed last
    for (uint32_t v = 0; v < params.maxDepth; ++v) {
        PclHit hit;
        const bool found = geometry.intersect(eyeRay(o, d, kInfinity, ray.time), hit);
        if (medium >= 0) {
            // The segment to the hit (or out of the scene) in this medium.
            const PclMedium& med = buffers.media[size_t(medium)];
            const float tEnd = found ? hit.t : kInfinity;
            if (maxComponent(eyeVec(med.sigmaS)) > 0.0f) {
                if (recorded.size() >= params.volumeSegments) {
                    h.flags = PCL_EYE_TRUNCATED;
                    break;
                }
                PclVolumeSegment sg{};
                sg.ox = o.x;
                sg.oy = o.y;
                sg.oz = o.z;
                const Vec3 centre(params.sceneCentre[0], params.sceneCentre[1], params.sceneCentre[2]);
                sg.length = found ? hit.t : eyeSphereExit(o, d, centre, params.sceneRadius);
                sg.dx = d.x;
                sg.dy = d.y;
                sg.dz = d.z;
                sg.time = ray.time;
                sg.throughput[0] = T.x;
                sg.throughput[1] = T.y;
                sg.throughput[2] = T.z;
                sg.medium = medium;
                sg.record = i;
                Le = Le + T * singleScatter(geometry, buffers, table, params, medium, o, d, tEnd, ray.time, seed, pixel,
                                            k, uint32_t(recorded.size()));
                recorded.push_back(sg);
            }
            T = T * eyeMediumTransmittance(med, tEnd);
        }
        if (!found) {
            if (skyActive(buffers)) {  // out to the sky; after a glossy lobe, its half of the MIS pair
                float pdfSky = 0.0f;
                const Vec3 Lsky = skyRadiance(buffers, d, &pdfSky);
                Le = Le + T * Lsky * (pdfLobe > 0.0f ? eyeMisWeight(1, pdfLobe, 1, pdfSky) : 1.0f);
            }
            break;
        }
        const Vec3 p = o + d * hit.t;
        const Vec3 n = eyeNormalAt(buffers, hit.prim, params.triangleCount, p, ray.time);
        const float dn = dot(d, n);
        const Vec3 nf = dn < 0.0f ? n : -n;
        const Vec3 ns = eyeShadingNormal(buffers, params.triangleCount, hit, n);  // the BSDF's frame
        const Vec3 sf = dn < 0.0f ? ns : -ns;
        const uint32_t mat = buffers.primInfo[hit.prim].material;
        const PclMaterial m = texturedMaterial(buffers, params.triangleCount, hit);  // ρd at the hit
        if (hasMedia) {
            if (m.flags & PCL_MATERIAL_INTERFACE) {
                // An invisible boundary: straight on in the medium beyond, not a hit of the chain.
                medium = dn < 0.0f ? buffers.primMedia[hit.prim].inside : buffers.primMedia[hit.prim].outside;
                o = p + nf * -params.rayEpsilon;
                travelled = travelled + hit.t;
                if (++crossings >= PCL_MAX_SEGMENTS) {
                    h.flags = PCL_EYE_TRUNCATED;
                    break;
                }
                --v;  // the loop's ++v
                continue;
            }
            crossings = 0;
        }
        const ShadowMedium sm{hasMedia, medium};
        if (dn < 0.0f) {  // a triangle light found by a glossy lobe: MIS with that hit's light sample
            float wE = 1.0f;
            const uint32_t l = table.lightOfPrim[hit.prim];
            const float r = travelled + hit.t;  // from the glossy hit, across invisible boundaries
            if (pdfLobe > 0.0f && l != PCL_NO_HIT && params.areaPowerTotal > 0.0f)
                wE = eyeMisWeight(1, pdfLobe, 1, eyeAreaLightPdf(buffers.lights[l], params.areaPowerTotal, d, r * r));
            Le = Le + T * eyeVec(m.emission) * wE;
        }
        const float pd = eyeDiffuseProbability(m);
        if (pd < 0.0f) break;
        if (m.specular == PCL_SPECULAR_GLOSSY && params.lightCount > 0) {  // direct light through the lobe
            const Vec3 lifted = p + nf * buffers.rayEpsilon;
            const float e = m.exponent;
            Vec3 sum(0.0f);
            for (uint32_t l = 0; l < params.lightCount; ++l) {
                const PclLight& L = buffers.lights[l];
                if (L.type == PCL_LIGHT_TRIANGLE || L.type == PCL_LIGHT_ENVIRONMENT) continue;
                Vec3 wi, tr;
                const float g = lightDelta(geometry, buffers, sm, L, p, nf, sf, lifted, ray.time, wi, tr);
                if (g > 0.0f) sum = sum + eyeVec(L.power) * (g * eyePhongCosPower(d, sf, wi, e)) * tr;
            }
            Vec3 wi, le;
            float pdfL, cosS;
            if (params.areaPowerTotal > 0.0f &&
                lightAreaSample(geometry, buffers, table, sm, params.lightCount, params.areaPowerTotal, p, nf, sf,
                                lifted, buffers.rayEpsilon, ray.time, sampler.vertex(v, PathVertexDims::kLightSelect),
                                sampler.vertex(v, PathVertexDims::kLightPoint),
                                sampler.vertex(v, PathVertexDims::kLightPoint + 1), wi, pdfL, cosS, le)) {
                const float cp = eyePhongCosPower(d, sf, wi, e);
                const float pdfB = (1.0f - pd) * ((e + 1.0f) / (2.0f * kPi)) * cp;
                sum = sum + le * (cp * cosS * eyeMisWeight(1, pdfL, 1, pdfB) / pdfL);
            }
            if (skyActive(buffers)) {  // the sky: one sample by its map, MIS against the lobe
                uint32_t ws[4];
                rng_block(seed, pixel, k, v, PCL_RNG_STREAM_EYE_SKY, ws);
                Vec3 wsky, lsky;
                float pdfSky, cosSky;
                if (lightSkySample(geometry, buffers, sm, nf, sf, lifted, ray.time, rng_u01(ws[0]), rng_u01(ws[1]),
                                   wsky, pdfSky, cosSky, lsky)) {
                    const float cp = eyePhongCosPower(d, sf, wsky, e);
                    const float pdfB = (1.0f - pd) * ((e + 1.0f) / (2.0f * kPi)) * cp;
                    sum = sum + lsky * (cp * cosSky * eyeMisWeight(1, pdfSky, 1, pdfB) / pdfSky);
                }
            }
            const float norm = (e + 2.0f) / (2.0f * kPi);
            Le = Le + T * eyeVec(m.rhoS) * Vec3(norm) * sum;
        }
        if (sampler.vertex(v, PathVertexDims::kLobe) < pd) {
            h.x = p.x;
            h.y = p.y;
            h.z = p.z;
            h.nx = nf.x;
            h.ny = nf.y;
            h.nz = nf.z;
            h.snx = sf.x;
            h.sny = sf.y;
            h.snz = sf.z;
            h.prim = hit.prim;
            h.wox = -d.x;
            h.woy = -d.y;
            h.woz = -d.z;
            const Vec3 t = T / Vec3(pd);
            h.throughput[0] = t.x;
            h.throughput[1] = t.y;
            h.throughput[2] = t.z;
            for (int c = 0; c < 3; ++c) h.albedo[c] = m.rhoD[c];
            h.material = mat;
            h.depth = v;
            h.flags = PCL_EYE_DIFFUSE;
            break;
        }
        Vec3 dNew, w;
        if (!eyeSpecularScatter(m, d, n, ns, sampler.vertex(v, 7), sampler.vertex(v, PathVertexDims::kDirection),
                                sampler.vertex(v, PathVertexDims::kDirection + 1), dNew, w))
            break;
        // Through the surface (refraction): the medium on the other side.
        if (hasMedia && dot(dNew, n) * dn > 0.0f)
            medium = dn < 0.0f ? buffers.primMedia[hit.prim].inside : buffers.primMedia[hit.prim].outside;
        T = T * w / Vec3(1.0f - pd);
        pdfLobe = m.specular == PCL_SPECULAR_GLOSSY
                      ? (1.0f - pd) * ((m.exponent + 1.0f) / (2.0f * kPi)) * eyePhongCosPower(d, sf, dNew, m.exponent)
                      : 0.0f;
        o = p + nf * (dot(dNew, nf) > 0.0f ? buffers.rayEpsilon : -buffers.rayEpsilon);
        d = dNew;
        travelled = 0.0f;
    }
    h.emitted[0] = Le.x;
    h.emitted[1] = Le.y;
    h.emitted[2] = Le.z;
    bool finite = true;
    for (int c = 0; c < 3; ++c) finite = finite && std::isfinite(h.throughput[c]) && std::isfinite(h.emitted[c]);
    for (const PclVolumeSegment& sg : recorded)
        for (int c = 0; c < 3; ++c) finite = finite && std::isfinite(sg.throughput[c]);
    if (!finite) {
        for (int c = 0; c < 4; ++c) h.throughput[c] = h.emitted[c] = 0.0f;
        h.prim = PCL_NO_HIT;
        h.flags = 0;
        recorded.clear();
    }
    if (segments) *segments = std::move(recorded);
    return h;
}

std::vector<PclEyeHit> referenceEyePaths(const SceneGeometry& geometry, const SceneBuffers& buffers,
                                         const std::vector<PclRay>& rays, const PclEyeParams& params,
                                         EyeVolumeSegments* segments) {
    const AreaLightTable table = buildAreaLightTable(buffers, geometry.primitiveCount());
    const size_t n = rays.size();
    std::vector<PclEyeHit> out(n);
    if (segments) {
        segments->perRecord = params.volumeSegments;
        segments->segments.assign(size_t(params.volumeSegments) * n, PclVolumeSegment{});
        segments->counts.assign(n, 0);
    }
    parallelForEveryThread(n, [&](size_t i) {
        std::vector<PclVolumeSegment> own;
        out[i] = referenceEyePath(geometry, buffers, table, params, rays[i], uint32_t(i), segments ? &own : nullptr);
        if (!segments) return;
        segments->counts[i] = uint32_t(own.size());
        for (size_t c = 0; c < own.size(); ++c) segments->segments[c * n + i] = own[c];
    });
    return out;
}

}  // namespace pcl
