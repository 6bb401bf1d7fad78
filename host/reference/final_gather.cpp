#include "reference/final_gather.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "reference/estimate.h"
#include "reference/eye_scatter.h"
#include "reference/knn.h"
#include "reference/light_sample.h"
#include "reference/parallel_for.h"
#include "reference/precomputed_irradiance.h"
#include "reference/shutter_open.h"
#include "reference/sky.h"
#include "reference/textured_material.h"
#include "reference/trace_photons.h"
#include "shared/rng.h"
#include "shared/stratify.h"

namespace pcl {

ReferenceIrradiance referenceEstimateIrradiance(const std::vector<PclPhoton>& map, const EstimateSettings& settings,
                                                const SceneGeometry* geometry) {
    return [&map, settings, geometry](const std::vector<PclEstimateQuery>& queries) {
        std::vector<PclEstimate> e = referenceEstimate(map, queries, settings, geometry);
        std::vector<Vec3> out(e.size());
        for (size_t i = 0; i < e.size(); ++i) out[i] = Vec3(e[i].r, e[i].g, e[i].b);
        return out;
    };
}

ReferenceIrradiance referencePrecomputedIrradiance(const std::vector<PclIrradiancePoint>& points,
                                                   const std::vector<float>& cover, float minNormalCos,
                                                   const std::vector<float>& nondirect) {
    return [&points, &cover, minNormalCos, &nondirect](const std::vector<PclEstimateQuery>& queries) {
        const ReferenceIrradianceLookup l =
            referenceLookupIrradiance(points, cover, queries, minNormalCos, 0, nondirect);
        std::vector<Vec3> out(queries.size());
        for (size_t j = 0; j < queries.size(); ++j)
            out[j] = Vec3(l.irradiance[4 * j], l.irradiance[4 * j + 1], l.irradiance[4 * j + 2]);
        return out;
    };
}

namespace {

// The photon's incoming direction (kernels/README.md, "Photon record"): θ = (θ byte + ½) π/256,
// φ = (signed φ byte + ½) π/128.
Vec3 decodePhotonDirection(uint32_t packed) {
    const float theta = (float(packed & 255u) + 0.5f) * (kPi / 256.0f);
    const uint32_t pb = (packed >> 8) & 255u;
    const int32_t ps = pb >= 128u ? int32_t(pb) - 256 : int32_t(pb);
    const float phi = (float(ps) + 0.5f) * (kPi / 128.0f);
    const float st = std::sin(theta);
    return {st * std::cos(phi), st * std::sin(phi), std::cos(theta)};
}

// The direct irradiance at a close gather hit (final_gather.cl, gather_direct): every delta light,
// one triangle-light sample and one sky sample, each weighted 1.
Vec3 gatherDirect(const SceneGeometry& geometry, const SceneBuffers& buffers, const AreaLightTable& table,
                  const PclGatherParams& params, uint64_t seed, uint32_t pixel, uint32_t bounceWord, float tau, Vec3 p,
                  Vec3 nf, Vec3 sf) {
    const float eps = params.rayEpsilon;
    const Vec3 o = p + nf * eps;
    const ShadowMedium sm;  // fg renders no media
    Vec3 E = lightDeltaIrradiance(geometry, buffers, sm, params.lightCount, p, nf, sf, o, tau, Vec3(0.0f));
    uint32_t w[4];
    if (params.areaPowerTotal > 0.0f) {
        rng_block(seed, pixel, bounceWord, PCL_GATHER_DIRECT_BLOCK, PCL_RNG_STREAM_GATHER, w);
        Vec3 wi, le;
        float pdfL, cosS;
        if (lightAreaSample(geometry, buffers, table, sm, params.lightCount, params.areaPowerTotal, p, nf, sf, o, eps,
                            tau, rng_u01(w[0]), rng_u01(w[1]), rng_u01(w[2]), wi, pdfL, cosS, le))
            E = E + le * (cosS / pdfL);
    }
    if (skyActive(buffers)) {
        rng_block(seed, pixel, bounceWord, PCL_GATHER_DIRECT_BLOCK + 1, PCL_RNG_STREAM_GATHER, w);
        Vec3 wi, le;
        float pdfL, cosS;
        if (lightSkySample(geometry, buffers, ShadowMedium{}, nf, sf, o, tau, rng_u01(w[0]), rng_u01(w[1]), wi, pdfL,
                           cosS, le))
            E = E + le * (cosS / pdfL);
    }
    return E;
}

}  // namespace

std::vector<float> referenceGatherHistograms(const std::vector<PclPhoton>& map, const std::vector<PclEyeHit>& hits,
                                             const PclGatherParams& params) {
    const uint32_t G = params.histogramCells, C = G * G;
    std::vector<PclKnnQuery> queries(hits.size());
    for (size_t i = 0; i < hits.size(); ++i) {
        queries[i] = PclKnnQuery{};
        queries[i].x = hits[i].x;
        queries[i].y = hits[i].y;
        queries[i].z = hits[i].z;
        queries[i].maxRadius2 = (hits[i].flags & PCL_EYE_DIFFUSE) ? params.maxRadius2 : 0.0f;
        queries[i].k = params.k;
    }
    const ReferenceKnn knn = referenceKnnBruteForce(map, queries);
    std::vector<float> out(hits.size() * C);
    for (size_t i = 0; i < hits.size(); ++i) {
        std::vector<float> f(C, 0.0f);
        float total = 0.0f;
        const PclEyeHit& h = hits[i];
        if (h.flags & PCL_EYE_DIFFUSE) {
            const Vec3 n(h.snx, h.sny, h.snz);  // the gather rays' frame
            for (uint32_t j = 0; j < knn.counts[i]; ++j) {
                const PclPhoton& ph = map[knn.indices[i * knn.stride + j]];
                const Vec3 wi = decodePhotonDirection(ph.packed);
                if (!(dot(wi, n) > 0.0f)) continue;
                const float flux = luminance(referenceDecodeRgbe(ph.rgbe));
                f[eyeCellOfDirection(n, wi, G)] += flux;
                total += flux;
            }
        }
        float running = 0.0f;
        for (uint32_t c = 0; c < C; ++c) {
            const float p = total > 0.0f
                                ? (1.0f - PCL_GATHER_UNIFORM_MIX) * (f[c] / total) + PCL_GATHER_UNIFORM_MIX / float(C)
                                : 1.0f / float(C);
            running += p;
            out[i * C + c] = c + 1 == C ? 1.0f : running;
        }
    }
    return out;
}

void referenceGatherRay(const SceneGeometry& geometry, const SceneBuffers& buffers, const AreaLightTable& table,
                        const PclGatherParams& params, const PclEyeHit& h, uint32_t g, PclEstimateQuery& q,
                        PclGatherHit& out, const float* cdf) {
    q = PclEstimateQuery{};
    q.nz = 1.0f;
    q.k = params.k;
    out = PclGatherHit{};
    if (!(h.flags & PCL_EYE_DIFFUSE)) return;
    const uint32_t N = params.gatherRays;
    const uint64_t seed = uint64_t(params.seedLo) | uint64_t(params.seedHi) << 32;
    const uint32_t bounceWord = h.sample * N + g;
    const Vec3 p0(h.x, h.y, h.z), n0(h.nx, h.ny, h.nz);
    const Vec3 s0(h.snx, h.sny, h.snz);  // the gather rays' frame: the shading normal
    const float tau = h.time;
    uint32_t w[4];
    rng_block(seed, h.pixel, bounceWord, 0, PCL_RNG_STREAM_GATHER, w);
    float s1 = rng_u01(w[0]), s2 = rng_u01(w[1]), ratio = 1.0f;
    const uint32_t G = params.histogramCells;
    // The pixel's n² N directions of this pass stratified together (shared/stratify.h): the
    // pass's pattern, shifted for the pixel. The kernel reads its cells from a table; the twin
    // permutes (stratify_cmj_cell) itself.
    uint32_t shift[4], pattern[4], cellA, cellB;
    rng_block(seed, h.pixel, PCL_GATHER_PATTERN_BOUNCE, 0, PCL_RNG_STREAM_GATHER, shift);
    rng_block(seed, PCL_PASS_PATTERN_PATH, PCL_GATHER_PATTERN_BOUNCE, 0, PCL_RNG_STREAM_GATHER, pattern);
    stratify_cmj_cell(bounceWord, params.samplesPerPixel * N, pattern[0], &cellA, &cellB);
    stratify_shifted(cellA, cellB, stratify_cells(params.samplesPerPixel * N), params.samplesPerPixel * N, s1, s2,
                     rng_u01(shift[0]), rng_u01(shift[1]), &s1, &s2);
    if (G > 0 && cdf) {
        // A cell by the table at s2, then s1 and s2's place in the cell's span within it.
        const uint32_t c = uint32_t(std::min<size_t>(std::upper_bound(cdf, cdf + G * G, s2) - cdf, G * G - 1));
        const float lo = c == 0 ? 0.0f : cdf[c - 1], span = cdf[c] - lo;
        const float t = std::min(span > 0.0f ? (s2 - lo) / span : 0.5f, 0x1.fffffep-1f);
        s1 = (float(c % G) + s1) / float(G);
        s2 = (float(c / G) + t) / float(G);
        ratio = 1.0f / (float(G * G) * eyeCellProbability(cdf, c));
    }
    Vec3 d = sampleCosineHemisphere(s0, s1, s2);
    const float pdfB = dot(s0, d) / kPi / ratio;
    if (eyeIsSmooth(s0, n0) && !(dot(d, n0) > 0.0f)) return;  // below the geometric surface: no light
    Vec3 o = p0 + n0 * params.rayEpsilon;
    Vec3 T(ratio), Le(0.0f);
    bool afterSpecular = false;
    float travelled = 0.0f;  // the path's length from the eye hit: how wide the map's blur looks
    for (uint32_t b = 0; b <= params.maxSpecular; ++b) {
        PclHit hit;
        if (!geometry.intersect(eyeRay(o, d, std::numeric_limits<float>::infinity(), tau), hit)) {
            // The sky: the gather half of the MIS pair with direct light's sky samples.
            if (skyActive(buffers) && !(afterSpecular && params.causticMapRead && params.causticSky)) {
                float pdfL;
                const Vec3 Lsky = skyRadiance(buffers, d, &pdfL);
                const float wMis =
                    !afterSpecular && params.lightSamples > 0 ? eyeMisWeight(N, pdfB, params.lightSamples, pdfL) : 1.0f;
                Le = Le + T * Lsky * Vec3(wMis);
            }
            break;
        }
        const Vec3 p = o + d * hit.t;
        travelled += hit.t;
        const Vec3 n = eyeNormalAt(buffers, hit.prim, params.triangleCount, p, tau);
        const float dn = dot(d, n);
        const Vec3 nf = dn < 0.0f ? n : -n;
        const PclMaterial m = texturedMaterial(buffers, params.triangleCount, hit);  // ρd at the hit
        // Light reached through a specular chain is the caustic map's when that is read.
        if (dn < 0.0f && maxComponent(eyeVec(m.emission)) > 0.0f && !(afterSpecular && params.causticMapRead)) {
            float wMis = 1.0f;
            const PclLight* light = nullptr;
            for (const PclLight& L : buffers.lights)  // the light entry of this triangle, if any
                if (L.type == PCL_LIGHT_TRIANGLE && L.prim == hit.prim) light = &L;
            if (!afterSpecular && light && params.lightSamples > 0) {
                const Vec3 toQ = p - p0;
                const float pdfL = eyeAreaLightPdf(*light, params.areaPowerTotal, d, dot(toQ, toQ));
                wMis = eyeMisWeight(N, pdfB, params.lightSamples, pdfL);
            }
            Le = Le + T * eyeVec(m.emission) * Vec3(wMis);
        }
        const float pd = eyeDiffuseProbability(m);
        if (pd < 0.0f) break;
        rng_block(seed, h.pixel, bounceWord, b + 1, PCL_RNG_STREAM_GATHER, w);
        if (rng_u01(w[0]) < pd) {
            const Vec3 pm = shutterOpenPosition(buffers.primInfo[hit.prim], p, tau);  // the map's place of p
            q.x = pm.x;
            q.y = pm.y;
            q.z = pm.z;
            q.nx = nf.x;
            q.ny = nf.y;
            q.nz = nf.z;
            q.maxRadius2 = params.maxRadius2;
            const Vec3 wt = T * (eyeVec(m.rhoD) / Vec3(kPi)) / Vec3(pd);
            out.weight[0] = wt.x;
            out.weight[1] = wt.y;
            out.weight[2] = wt.z;
            if (travelled < params.closeDistance) {
                // A short gather path (through mirrors too): its direct part by shadow rays, the map for the rest.
                const Vec3 ns = eyeShadingNormal(buffers, params.triangleCount, hit, n);
                const Vec3 sf = dn < 0.0f ? ns : -ns;
                const Vec3 E =
                    gatherDirect(geometry, buffers, table, params, seed, h.pixel, bounceWord, tau, p, nf, sf);
                Le = Le + wt * E;
                q.k = params.k | PCL_QUERY_NONDIRECT;
            }
            break;
        }
        if (b == params.maxSpecular) break;
        Vec3 dNew, ws;
        const Vec3 ns = eyeShadingNormal(buffers, params.triangleCount, hit, n);
        if (!eyeSpecularScatter(m, d, n, ns, rng_u01(w[1]), rng_u01(w[2]), rng_u01(w[3]), dNew, ws)) break;
        T = T * ws / Vec3(1.0f - pd);
        o = p + nf * (dot(dNew, nf) > 0.0f ? params.rayEpsilon : -params.rayEpsilon);
        d = dNew;
        afterSpecular = true;
    }
    out.emitted[0] = std::isfinite(Le.x) ? Le.x : 0.0f;
    out.emitted[1] = std::isfinite(Le.y) ? Le.y : 0.0f;
    out.emitted[2] = std::isfinite(Le.z) ? Le.z : 0.0f;
    for (int c = 0; c < 3; ++c)
        if (!std::isfinite(out.weight[c])) out.weight[c] = 0.0f;
}

std::vector<PclRadiance> referenceResolveGather(const PclGatherParams& params, const std::vector<PclEyeHit>& hits,
                                                const std::vector<PclGatherHit>& gathered,
                                                const std::vector<Vec3>& irradiance) {
    std::vector<PclRadiance> out(hits.size());
    const uint32_t N = params.gatherRays;
    for (size_t i = 0; i < hits.size(); ++i) {
        const PclEyeHit& h = hits[i];
        if (!(h.flags & PCL_EYE_DIFFUSE)) continue;
        float sum[3] = {0.0f, 0.0f, 0.0f};
        for (uint32_t g = 0; g < N; ++g) {
            const size_t j = i * N + g;
            const float E[3] = {irradiance[j].x, irradiance[j].y, irradiance[j].z};
            for (int c = 0; c < 3; ++c) sum[c] = sum[c] + (gathered[j].weight[c] * E[c] + gathered[j].emitted[c]);
        }
        float L3[3];
        for (int c = 0; c < 3; ++c) {
            L3[c] = h.throughput[c] * h.albedo[c] * (sum[c] / float(N));
            if (!std::isfinite(L3[c])) L3[c] = 0.0f;
        }
        out[i] = PclRadiance{L3[0], L3[1], L3[2], 0.0f};
    }
    return out;
}

ReferenceGather referenceFinalGather(const SceneGeometry& geometry, const SceneBuffers& buffers,
                                     const std::vector<PclEyeHit>& hits, const PclGatherParams& params,
                                     const ReferenceIrradiance& irradiance, const std::vector<float>* histograms) {
    ReferenceGather r;
    const AreaLightTable table = buildAreaLightTable(buffers, geometry.primitiveCount());
    const size_t N = params.gatherRays, n = hits.size() * N;
    r.queries.resize(n);
    r.gathered.resize(n);
    parallelForEveryThread(n, [&](size_t j) {
        const size_t C = size_t(params.histogramCells) * params.histogramCells;
        const float* cdf = (C > 0 && histograms) ? histograms->data() + (j / N) * C : nullptr;
        referenceGatherRay(geometry, buffers, table, params, hits[j / N], uint32_t(j % N), r.queries[j], r.gathered[j],
                           cdf);
    });
    r.irradiance = irradiance(r.queries);
    r.radiance = referenceResolveGather(params, hits, r.gathered, r.irradiance);
    return r;
}

}  // namespace pcl
