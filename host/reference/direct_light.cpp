#include "reference/direct_light.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "reference/eye_scatter.h"
#include "reference/parallel_for.h"
#include "shared/rng.h"

namespace pcl {
namespace {

float smoothstep(float e0, float e1, float x) {
    if (e1 <= e0) return x >= e1 ? 1.0f : 0.0f;
    const float t = std::min(1.0f, std::max(0.0f, (x - e0) / (e1 - e0)));
    return t * t * (3.0f - 2.0f * t);
}

}  // namespace

PclRadiance referenceDirectLightAt(const SceneGeometry& geometry, const SceneBuffers& buffers,
                                   const AreaLightTable& table, const PclDirectParams& params, const PclEyeHit& h,
                                   const float* cdf) {
    PclRadiance out{};
    if (!(h.flags & PCL_EYE_DIFFUSE)) return out;
    const Vec3 p(h.x, h.y, h.z), nf(h.nx, h.ny, h.nz);
    const float eps = params.rayEpsilon, tau = h.time;
    const Vec3 o = p + nf * eps;
    const float inf = std::numeric_limits<float>::infinity();
    Vec3 sum(0.0f);
    for (uint32_t l = 0; l < params.lightCount; ++l) {
        const PclLight& L = buffers.lights[l];
        const Vec3 phi = eyeVec(L.power);
        if (L.type == PCL_LIGHT_TRIANGLE) continue;
        if (L.type == PCL_LIGHT_DIRECTIONAL) {
            const Vec3 wi = -eyeVec(L.axis);
            const float cosS = dot(nf, wi);
            if (!(cosS > 0.0f) || geometry.occluded(eyeRay(o, wi, inf, tau))) continue;
            sum = sum + phi * (cosS / (kPi * L.radius * L.radius));  // E = Φ/(πR²), × cosθ
            continue;
        }
        const Vec3 toL = eyeVec(L.p) - p;
        const float d2 = dot(toL, toL);
        if (!(d2 > 0.0f)) continue;
        const float dist = std::sqrt(d2);
        const Vec3 wi(toL.x / dist, toL.y / dist, toL.z / dist);
        const float cosS = dot(nf, wi);
        if (!(cosS > 0.0f)) continue;
        float scale;  // I/Φ with the spot's falloff
        if (L.type == PCL_LIGHT_POINT) {
            scale = 1.0f / (4.0f * kPi);
        } else {
            const float falloff = smoothstep(L.cosOuter, L.cosInner, -dot(eyeVec(L.axis), wi));
            if (!(falloff > 0.0f)) continue;
            scale = falloff / (2.0f * kPi * ((1.0f - L.cosInner) + 0.5f * (L.cosInner - L.cosOuter)));
        }
        if (geometry.occluded(eyeRay(o, eyeVec(L.p) - o, 1.0f, tau))) continue;
        sum = sum + phi * (scale * cosS / d2);
    }
    const uint32_t M = params.lightSamples;
    if (params.areaPowerTotal > 0.0f && M > 0) {
        const uint64_t seed = uint64_t(params.seedLo) | uint64_t(params.seedHi) << 32;
        Vec3 area(0.0f);
        for (uint32_t m = 0; m < M; ++m) {
            uint32_t w[4];
            rng_block(seed, h.pixel, h.sample * M + m, 0, PCL_RNG_STREAM_LIGHT, w);
            const float u0 = rng_u01(w[0]);
            // The first light whose cumulative probability exceeds u0.
            const size_t l = std::min<size_t>(
                std::upper_bound(table.cdf.begin(), table.cdf.end(), u0) - table.cdf.begin(), params.lightCount - 1);
            const PclLight& L = buffers.lights[l];
            if (L.type != PCL_LIGHT_TRIANGLE) continue;
            float b0, b1;
            sampleUniformTriangle(rng_u01(w[1]), rng_u01(w[2]), b0, b1);
            const float b2 = 1.0f - b0 - b1;
            const Vec3 q = eyeVec(L.p) + eyeVec(L.e1) * b1 + eyeVec(L.e2) * b2 + eyeVec(L.motion) * tau;
            const Vec3 toL = q - p;
            const float d2 = dot(toL, toL);
            if (!(d2 > 0.0f)) continue;
            const float dist = std::sqrt(d2);
            const Vec3 wi(toL.x / dist, toL.y / dist, toL.z / dist);
            const float cosS = dot(nf, wi);
            if (!(cosS > 0.0f)) continue;
            const float pdfL = eyeAreaLightPdf(L, params.areaPowerTotal, wi, d2);
            if (!(pdfL > 0.0f)) continue;
            const Vec3 end = q + eyeVec(L.axis) * eps;
            if (geometry.occluded(eyeRay(o, end - o, 1.0f, tau))) continue;
            float pdfB = cosS / kPi;
            if (params.histogramCells > 0 && cdf) {
                const uint32_t G = params.histogramCells;
                pdfB = pdfB * (float(G * G) * eyeCellProbability(cdf, eyeCellOfDirection(nf, wi, G)));
            }
            const float wMis = params.gatherRays == 0 ? 1.0f : eyeMisWeight(M, pdfL, params.gatherRays, pdfB);
            const Vec3 Le = eyeVec(buffers.materials[buffers.primInfo[L.prim].material].emission);
            area = area + Le * (cosS * wMis / pdfL);
        }
        sum = sum + area / Vec3(float(M));
    }
    const Vec3 T = eyeVec(h.throughput), rho = eyeVec(h.albedo);
    Vec3 L3 = T * (rho / Vec3(kPi)) * sum;
    out.r = std::isfinite(L3.x) ? L3.x : 0.0f;
    out.g = std::isfinite(L3.y) ? L3.y : 0.0f;
    out.b = std::isfinite(L3.z) ? L3.z : 0.0f;
    return out;
}

std::vector<PclRadiance> referenceDirectLight(const SceneGeometry& geometry, const SceneBuffers& buffers,
                                              const std::vector<PclEyeHit>& hits, const PclDirectParams& params,
                                              const std::vector<float>* histograms) {
    const AreaLightTable table = buildAreaLightTable(buffers, geometry.primitiveCount());
    std::vector<PclRadiance> out(hits.size());
    parallelForEveryThread(hits.size(), [&](size_t i) {
        const size_t C = size_t(params.histogramCells) * params.histogramCells;
        const float* cdf = (C > 0 && histograms) ? histograms->data() + i * C : nullptr;
        out[i] = referenceDirectLightAt(geometry, buffers, table, params, hits[i], cdf);
    });
    return out;
}

}  // namespace pcl
