#include "reference/direct_light.h"

#include <algorithm>
#include <cmath>

#include "reference/eye_scatter.h"
#include "reference/light_sample.h"
#include "reference/parallel_for.h"
#include "reference/sky.h"
#include "shared/rng.h"
#include "shared/stratify.h"

namespace pcl {

PclRadiance referenceDirectLightAt(const SceneGeometry& geometry, const SceneBuffers& buffers,
                                   const AreaLightTable& table, const PclDirectParams& params, const PclEyeHit& h,
                                   const float* cdf) {
    PclRadiance out{};
    if (!(h.flags & PCL_EYE_DIFFUSE)) return out;
    const Vec3 p(h.x, h.y, h.z), nf(h.nx, h.ny, h.nz);
    const Vec3 sf(h.snx, h.sny, h.snz);  // the shading normal: cosines and the gather rays' frame
    const float eps = params.rayEpsilon, tau = h.time;
    const Vec3 o = p + nf * eps;
    // Shadow rays start in the medium on the record's side of its surface.
    ShadowMedium sm;
    sm.hasMedia = params.hasMedia != 0;
    if (sm.hasMedia) {
        const Vec3 n = eyeNormalAt(buffers, h.prim, params.triangleCount, p, tau);
        sm.medium = dot(nf, n) > 0.0f ? buffers.primMedia[h.prim].outside : buffers.primMedia[h.prim].inside;
    }
    Vec3 sum = lightDeltaIrradiance(geometry, buffers, sm, params.lightCount, p, nf, sf, o, tau, Vec3(0.0f));
    const uint32_t M = params.lightSamples;
    // The pixel's n² M light points and sky directions of this pass, each stratified together:
    // the pass's two patterns, shifted for the pixel. The kernel reads their cells from a table;
    // the twin permutes (stratify_cmj_cell) itself.
    const uint64_t seed = uint64_t(params.seedLo) | uint64_t(params.seedHi) << 32;
    const uint32_t count = params.samplesPerPixel * M, cells = stratify_cells(count);
    uint32_t shift[4] = {0, 0, 0, 0}, pattern[4] = {0, 0, 0, 0};
    if (M > 0 && (params.areaPowerTotal > 0.0f || skyActive(buffers))) {  // none for delta lights alone
        rng_block(seed, h.pixel, PCL_LIGHT_PATTERN_BOUNCE, 0, PCL_RNG_STREAM_LIGHT, shift);
        rng_block(seed, PCL_PASS_PATTERN_PATH, PCL_LIGHT_PATTERN_BOUNCE, 0, PCL_RNG_STREAM_LIGHT, pattern);
    }
    if (params.areaPowerTotal > 0.0f && M > 0) {
        Vec3 area(0.0f);
        for (uint32_t m = 0; m < M; ++m) {
            uint32_t w[4];
            rng_block(seed, h.pixel, h.sample * M + m, 0, PCL_RNG_STREAM_LIGHT, w);
            float u1, u2;
            uint32_t cellA, cellB;
            stratify_cmj_cell(h.sample * M + m, count, pattern[0], &cellA, &cellB);
            stratify_shifted(cellA, cellB, cells, count, rng_u01(w[1]), rng_u01(w[2]), rng_u01(shift[0]),
                             rng_u01(shift[1]), &u1, &u2);
            Vec3 wi, le;
            float pdfL, cosS;
            if (!lightAreaSample(geometry, buffers, table, sm, params.lightCount, params.areaPowerTotal, p, nf, sf, o,
                                 eps, tau, rng_u01(w[0]), u1, u2, wi, pdfL, cosS, le))
                continue;
            float pdfB = cosS / kPi;
            if (params.histogramCells > 0 && cdf) {
                const uint32_t G = params.histogramCells;
                pdfB = pdfB * (float(G * G) * eyeCellProbability(cdf, eyeCellOfDirection(sf, wi, G)));
            }
            const float wMis = params.gatherRays == 0 ? 1.0f : eyeMisWeight(M, pdfL, params.gatherRays, pdfB);
            area = area + le * (cosS * wMis / pdfL);
        }
        sum = sum + area / Vec3(float(M));
    }
    // The sky: M samples by its map (block 1 of the same counters), MIS against the gather rays.
    if (skyActive(buffers) && M > 0) {
        Vec3 sky(0.0f);
        for (uint32_t m = 0; m < M; ++m) {
            uint32_t w[4];
            rng_block(seed, h.pixel, h.sample * M + m, 1, PCL_RNG_STREAM_LIGHT, w);
            float u0, u1;
            uint32_t cellA, cellB;
            stratify_cmj_cell(h.sample * M + m, count, pattern[1], &cellA, &cellB);
            stratify_shifted(cellA, cellB, cells, count, rng_u01(w[0]), rng_u01(w[1]), rng_u01(shift[2]),
                             rng_u01(shift[3]), &u0, &u1);
            Vec3 wi, le;
            float pdfL, cosS;
            if (!lightSkySample(geometry, buffers, sm, nf, sf, o, tau, u0, u1, wi, pdfL, cosS, le)) continue;
            float pdfB = cosS / kPi;
            if (params.histogramCells > 0 && cdf) {
                const uint32_t G = params.histogramCells;
                pdfB = pdfB * (float(G * G) * eyeCellProbability(cdf, eyeCellOfDirection(sf, wi, G)));
            }
            const float wMis = params.gatherRays == 0 ? 1.0f : eyeMisWeight(M, pdfL, params.gatherRays, pdfB);
            sky = sky + le * (cosS * wMis / pdfL);
        }
        sum = sum + sky / Vec3(float(M));
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
