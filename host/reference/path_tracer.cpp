#include "reference/path_tracer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <thread>
#include <vector>

#include "core/clock.h"
#include "reference/bsdf.h"
#include "reference/sampling.h"
#include "reference/surface.h"

namespace pcl {

PathTracer::PathTracer(const Scene& scene, const SceneGeometry& geometry, PathTracerSettings settings)
    : scene_(scene), geometry_(geometry), settings_(std::move(settings)), camera_(scene.camera),
      lights_(scene, geometry) {}

// Next-event estimation at s: one light sample, weighted against BSDF sampling by the power
// heuristic when the light is an area (the BSDF could have found it too); delta lights get weight 1.
Vec3 PathTracer::sampleDirect(const SurfacePoint& s, const MixedBsdf& bsdf, Vec3 wo, Sampler& sampler,
                              uint32_t vertex) const {
    LightSample ls;
    if (!lights_.sampleLi(s.p, s.time, sampler.vertex(vertex, PathVertexDims::kLightSelect),
                          sampler.vertex(vertex, PathVertexDims::kLightPoint),
                          sampler.vertex(vertex, PathVertexDims::kLightPoint + 1), ls))
        return Vec3(0.0f);
    Vec3 fCos = bsdf.evalCos(wo, ls.wi);
    if (maxComponent(fCos) <= 0.0f) return Vec3(0.0f);
    PclRay shadow = ls.infinite ? spawnRay(s.p, s.ng, ls.wi, s.time, std::numeric_limits<float>::infinity())
                                : spawnShadowRay(s.p, s.ng, ls.point, ls.normal, s.time);
    if (geometry_.occluded(shadow)) return Vec3(0.0f);
    float weight = ls.delta ? 1.0f : powerHeuristic(ls.pdf, bsdf.pdf(wo, ls.wi));
    return fCos * ls.Li * (weight / ls.pdf);
}

// The path integral estimator of pbrt-v4 §13.4 (PathIntegrator): at each vertex, emission
// found by the BSDF-sampled ray (MIS-weighted), then a light sample, then the next direction.
Vec3 PathTracer::Li(PclRay ray, Sampler& sampler) const {
    Vec3 L(0.0f), beta(1.0f);
    // The product of the refractions' radiance scales undone for Russian roulette (pbrt-v4's
    // etaScale): inside glass beta is 1/η² smaller without the path being any less worth tracing.
    float rouletteScale = 1.0f;
    bool specularBounce = true;  // the camera ray counts as specular: emitters seen directly count fully
    float prevPdf = 0.0f;
    Vec3 prevP;
    for (int depth = 0;; ++depth) {
        PclHit hit;
        if (!geometry_.intersect(ray, hit)) break;  // no environment light: nothing arrives from outside
        SurfacePoint s = surfaceAt(scene_, geometry_, ray, hit);
        Vec3 wo = -normalize(rayDirection(ray));

        Vec3 Le = LightSampler::emitted(s, wo);
        if (maxComponent(Le) > 0.0f) {
            float weight = 1.0f;
            if (!specularBounce && settings_.lightSampling)
                weight = powerHeuristic(prevPdf, lights_.pdfLi(s.prim, prevP, s.p, s.ng));
            L += beta * Le * weight;
        }
        if (depth >= settings_.maxDepth) break;

        MixedBsdf bsdf(*s.material, s.ns, s.ng);
        if (bsdf.isBlack()) break;
        uint32_t vertex = static_cast<uint32_t>(depth);
        if (bsdf.hasNonDelta() && settings_.lightSampling) L += beta * sampleDirect(s, bsdf, wo, sampler, vertex);

        BsdfSample bs;
        if (!bsdf.sample(wo, sampler.vertex(vertex, PathVertexDims::kLobe),
                         sampler.vertex(vertex, PathVertexDims::kDirection),
                         sampler.vertex(vertex, PathVertexDims::kDirection + 1), bs))
            break;
        beta *= bs.weight;
        rouletteScale /= bs.radianceScale;
        specularBounce = bs.delta;
        prevPdf = bs.pdf;
        prevP = s.p;
        ray = spawnRay(s.p, s.ng, bs.wi, s.time, std::numeric_limits<float>::infinity());

        // Russian roulette (Arvo & Kirk 1990): end with probability q, divide survivors by 1 - q.
        if (depth + 1 >= settings_.rouletteDepth) {
            float q = std::max(0.05f, 1.0f - maxComponent(beta) * rouletteScale);
            if (sampler.vertex(vertex, PathVertexDims::kRoulette) < q) break;
            beta *= 1.0f / (1.0f - q);
        }
        if (maxComponent(beta) <= 0.0f) break;
    }
    return L;
}

Film PathTracer::render(PathTracerStats* stats) const {
    const int width = scene_.camera.width, height = scene_.camera.height;
    Film film(width, height);
    constexpr int kTile = 16;
    const int tilesX = (width + kTile - 1) / kTile, tilesY = (height + kTile - 1) / kTile;
    const int tileCount = tilesX * tilesY;
    int threads = settings_.threads > 0 ? settings_.threads : static_cast<int>(std::thread::hardware_concurrency());
    threads = std::max(1, std::min(threads, tileCount));

    std::atomic<int> nextTile{0};
    std::atomic<uint64_t> discarded{0};
    std::mutex progressMutex;
    int tilesDone = 0;
    auto start = std::chrono::steady_clock::now();

    // Each tile's pixels belong to one thread, and each pixel's samples are added in order, so
    // the film is the same bits for any thread count.
    auto worker = [&]() {
        for (int tile; (tile = nextTile.fetch_add(1)) < tileCount;) {
            int x0 = (tile % tilesX) * kTile, y0 = (tile / tilesX) * kTile;
            for (int y = y0; y < std::min(y0 + kTile, height); ++y)
                for (int x = x0; x < std::min(x0 + kTile, width); ++x) {
                    uint32_t pixel = static_cast<uint32_t>(y) * static_cast<uint32_t>(width) + static_cast<uint32_t>(x);
                    for (int i = 0; i < settings_.samplesPerPixel; ++i) {
                        Sampler sampler(settings_.seed, pixel, static_cast<uint32_t>(settings_.firstSample + i));
                        CameraSample cs;
                        cs.filmX = sampler.get(CameraDims::kFilm);
                        cs.filmY = sampler.get(CameraDims::kFilm + 1);
                        cs.lensU = sampler.get(CameraDims::kLens);
                        cs.lensV = sampler.get(CameraDims::kLens + 1);
                        cs.time = sampler.get(CameraDims::kTime);
                        Vec3 L = Li(camera_.generateRay(x, y, cs), sampler);
                        if (!isFinite(L)) {  // keep one bad path from ruining the pixel; counted
                            discarded.fetch_add(1, std::memory_order_relaxed);
                            L = Vec3(0.0f);
                        }
                        film.add(x, y, L);
                    }
                }
            if (settings_.progress) {
                std::lock_guard<std::mutex> lock(progressMutex);
                settings_.progress(static_cast<double>(++tilesDone) / tileCount);
            }
        }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();

    if (stats) {
        stats->seconds = since(start);
        stats->samples = static_cast<uint64_t>(width) * height *
                         static_cast<uint64_t>(std::max(0, settings_.samplesPerPixel));
        stats->discardedSamples = discarded.load();
    }
    return film;
}

}  // namespace pcl
