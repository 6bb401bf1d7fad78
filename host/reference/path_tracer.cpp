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
#include "reference/medium.h"
#include "reference/sampling.h"
#include "reference/surface.h"

namespace pcl {

PathTracer::PathTracer(const Scene& scene, const SceneGeometry& geometry, PathTracerSettings settings)
    : scene_(scene), geometry_(geometry), settings_(std::move(settings)), camera_(scene.camera),
      lights_(scene, geometry), hasMedia_(scene.hasMedia()) {
    if (hasMedia_) boundaries_ = findMediumBoundaries(scene, geometry);
    if (hasMedia_ && settings_.equiangular && settings_.lightSampling) {
        float total = 0.0f;
        for (size_t e = 0; e < lights_.count(); ++e)
            if (lights_.isPositional(e) && lights_.probability(e) > 0.0f) {
                positional_.push_back(e);
                positionalCdf_.push_back(total += lights_.probability(e));
            }
        for (float& c : positionalCdf_) c /= total;
    }
}

float PathTracer::equiangularChoice(size_t emitter) const {
    for (size_t i = 0; i < positional_.size(); ++i)
        if (positional_[i] == emitter) return positionalCdf_[i] - (i > 0 ? positionalCdf_[i - 1] : 0.0f);
    return 0.0f;
}

namespace {

// A path crosses at most this many invisible medium boundaries per shadow ray, and has at most
// this many vertices (boundary crossings do not count toward maxDepth): a guard, never reached in
// a sane scene.
constexpr int kMaxBoundaryCrossings = 256;
constexpr uint32_t kMaxVertices = 4096;

}  // namespace

Vec3 PathTracer::shadowTransmittance(PclRay shadow, int32_t medium) const {
    if (!hasMedia_) return geometry_.occluded(shadow) ? Vec3(0.0f) : Vec3(1.0f);
    const float length = pcl::length(rayDirection(shadow));
    Vec3 tr(1.0f);
    float start = shadow.tmin;  // where the current medium began along the ray
    for (int crossing = 0; crossing < kMaxBoundaryCrossings; ++crossing) {
        PclHit hit;
        const bool found = geometry_.intersect(shadow, hit);
        const float end = found ? hit.t : shadow.tmax;
        if (medium >= 0) tr *= pcl::transmittance(scene_.media[size_t(medium)].sigmaT(), (end - start) * length);
        if (!found) return tr;
        const SurfacePoint s = surfaceAt(scene_, geometry_, shadow, hit);
        if (!s.material->interface) return Vec3(0.0f);
        // Through the boundary into the medium beyond: the search goes on past the hit by the
        // offset spawnRay uses, the medium's length is counted from the hit itself.
        medium = boundaries_.beyond(s.prim, dot(s.ng, rayDirection(shadow)));
        start = hit.t;
        shadow.tmin = hit.t + 1e-4f * std::max(1.0f, maxComponent(vmax(s.p, -s.p))) / length;
        if (!(shadow.tmin < shadow.tmax)) return tr;
    }
    return Vec3(0.0f);
}

Vec3 PathTracer::transmittance(Vec3 from, Vec3 to, float time) const {
    PclRay r = spawnRay(from, Vec3(0.0f), to - from, time, 1.0f);
    return shadowTransmittance(r, hasMedia_ ? mediumAt(scene_, from) : -1);
}

// Next-event estimation at s: one light sample, weighted against BSDF sampling by the power
// heuristic when the light is an area (the BSDF could have found it too); delta lights get weight 1.
// The shadow ray starts in `medium`, the one on wo's side (the non-delta lobes only reflect).
Vec3 PathTracer::sampleDirect(const SurfacePoint& s, const MixedBsdf& bsdf, Vec3 wo, int32_t medium, Sampler& sampler,
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
    const Vec3 tr = shadowTransmittance(shadow, medium);
    if (maxComponent(tr) <= 0.0f) return Vec3(0.0f);
    float weight = ls.delta ? 1.0f : powerHeuristic(ls.pdf, bsdf.pdf(wo, ls.wi));
    return fCos * ls.Li * (weight / ls.pdf) * tr;
}

// Next-event estimation at a scattering event at distance t along `segment` in `medium`: the
// phase function in place of f cos θ, MIS against phase sampling for area lights and against the
// segment's equiangular sample for positional lights (the same (light, t) pair, found by two
// densities: choice × free flight here, equiangular choice × equiangular distance there).
Vec3 PathTracer::sampleDirectInMedium(Vec3 p, Vec3 wo, float time, int32_t medium, const MediumSegment& segment,
                                      float t, Sampler& sampler, uint32_t vertex) const {
    LightSample ls;
    if (!lights_.sampleLi(p, time, sampler.vertex(vertex, PathVertexDims::kLightSelect),
                          sampler.vertex(vertex, PathVertexDims::kLightPoint),
                          sampler.vertex(vertex, PathVertexDims::kLightPoint + 1), ls))
        return Vec3(0.0f);
    const Medium& m = scene_.media[size_t(medium)];
    const float phase = henyeyGreenstein(dot(-wo, ls.wi), m.g);
    PclRay shadow = ls.infinite ? spawnRay(p, Vec3(0.0f), ls.wi, time, std::numeric_limits<float>::infinity())
                                : spawnShadowRay(p, Vec3(0.0f), ls.point, ls.normal, time);
    const Vec3 tr = shadowTransmittance(shadow, medium);
    if (maxComponent(tr) <= 0.0f) return Vec3(0.0f);
    float weight = ls.delta ? 1.0f : powerHeuristic(ls.pdf, phase);
    if (const float choice = equiangularChoice(ls.emitter); choice > 0.0f)
        weight = powerHeuristic(ls.pdf * freeFlightPdf(m, t, segment.beta),
                                choice * equiangularPdf(segment.origin, segment.dir, segment.length, ls.point, t));
    return ls.Li * tr * (phase * weight / ls.pdf);
}

// The other half of that pair: a positional light chosen by power, a distance t on the segment
// by equiangular sampling toward it, and the light it sends to the eye from there: σs Tr(t) p Li
// Tr(shadow) over the density, MIS-weighted. Returned per unit of the segment's throughput.
Vec3 PathTracer::sampleEquiangular(const MediumSegment& segment, float time, int32_t medium, Sampler& sampler,
                                   uint32_t vertex) const {
    if (positional_.empty()) return Vec3(0.0f);
    const Medium& m = scene_.media[size_t(medium)];
    if (!(maxComponent(m.sigmaS) > 0.0f)) return Vec3(0.0f);
    const float u = sampler.vertex(vertex, 0);
    size_t i = std::upper_bound(positionalCdf_.begin(), positionalCdf_.end(), u) - positionalCdf_.begin();
    i = std::min(i, positional_.size() - 1);
    const size_t emitter = positional_[i];
    const float choice = equiangularChoice(emitter);
    float t, pdf;
    if (!(choice > 0.0f) || !pcl::sampleEquiangular(segment.origin, segment.dir, segment.length,
                                                    lights_.positionOf(emitter), sampler.vertex(vertex, 1), t, pdf))
        return Vec3(0.0f);
    const Vec3 p = segment.origin + segment.dir * t;
    LightSample ls;
    if (!lights_.sampleLiFrom(emitter, p, time, 0.0f, 0.0f, ls)) return Vec3(0.0f);
    const float phase = henyeyGreenstein(dot(segment.dir, ls.wi), m.g);
    const Vec3 tr = shadowTransmittance(spawnShadowRay(p, Vec3(0.0f), ls.point, ls.normal, time), medium);
    if (maxComponent(tr) <= 0.0f) return Vec3(0.0f);
    const float pdfEquiangular = choice * pdf;
    // The free flight finds (emitter, t) only as a scattering event before the segment's end.
    const float pdfFlight = t < segment.length ? ls.pdf * freeFlightPdf(m, t, segment.beta) : 0.0f;
    const float weight = powerHeuristic(pdfEquiangular, pdfFlight);
    return m.sigmaS * pcl::transmittance(m.sigmaT(), t) * ls.Li * tr * (phase * weight / pdfEquiangular);
}

// The path integral estimator of pbrt-v4 §13.4 (PathIntegrator), with media as in its
// VolPathIntegrator (§14.2) for homogeneous media: on each segment inside a medium a free-flight
// distance decides between a scattering event and the surface; at a scattering event a light
// sample and a phase-sampled direction, at a surface the emission found (MIS-weighted), a light
// sample and a BSDF-sampled direction.
Vec3 PathTracer::Li(PclRay ray, Sampler& sampler) const {
    Vec3 L(0.0f), beta(1.0f);
    // The product of the refractions' radiance scales undone for Russian roulette (pbrt-v4's
    // etaScale): inside glass beta is 1/η² smaller without the path being any less worth tracing.
    float rouletteScale = 1.0f;
    bool specularBounce = true;  // the camera ray counts as specular: emitters seen directly count fully
    float prevPdf = 0.0f;
    Vec3 prevP;
    int32_t medium = hasMedia_ ? boundaries_.cameraMedium : -1;  // the medium the ray travels in
    Sampler equiangular = sampler.withStream(PCL_RNG_STREAM_EQUIANGULAR);
    int depth = 0;  // scattering events so far (surfaces and media)
    // Where the current medium began along the ray (its parameter): past an invisible boundary the
    // ray goes on from the boundary, and the search for the next hit from just beyond it.
    float segmentStart = 0.0f;
    for (uint32_t vertex = 0; vertex < kMaxVertices; ++vertex) {
        PclHit hit;
        const bool found = geometry_.intersect(ray, hit);
        if (medium >= 0) {
            const Medium& m = scene_.media[size_t(medium)];
            const Vec3 d = rayDirection(ray);
            const float length = pcl::length(d);
            const MediumSegment segment{
                rayOrigin(ray) + d * segmentStart, d / length,
                found ? (hit.t - segmentStart) * length : std::numeric_limits<float>::infinity(), beta};
            if (!positional_.empty() && depth < settings_.maxDepth)
                L += beta * sampleEquiangular(segment, ray.time, medium, equiangular, vertex);
            const FreeFlight flight =
                sampleFreeFlight(m, segment.length, sampler.vertex(vertex, PathVertexDims::kFreeFlight), beta);
            beta *= flight.weight;
            if (!(maxComponent(beta) > 0.0f)) break;
            if (flight.scattered) {
                if (depth >= settings_.maxDepth) break;
                const Vec3 wo = -segment.dir;
                const Vec3 p = segment.origin + segment.dir * flight.t;
                if (settings_.lightSampling)
                    L += beta * sampleDirectInMedium(p, wo, ray.time, medium, segment, flight.t, sampler, vertex);
                // The phase function is sampled exactly: the weight p/pdf is 1.
                const Vec3 wi = sampleHenyeyGreenstein(wo, m.g, sampler.vertex(vertex, PathVertexDims::kDirection),
                                                       sampler.vertex(vertex, PathVertexDims::kDirection + 1));
                specularBounce = false;
                prevPdf = henyeyGreenstein(dot(-wo, wi), m.g);
                prevP = p;
                ray = spawnRay(p, Vec3(0.0f), wi, ray.time, std::numeric_limits<float>::infinity());
                segmentStart = 0.0f;
                if (depth + 1 >= settings_.rouletteDepth) {
                    float q = std::max(0.05f, 1.0f - maxComponent(beta) * rouletteScale);
                    if (sampler.vertex(vertex, PathVertexDims::kRoulette) < q) break;
                    beta *= 1.0f / (1.0f - q);
                }
                ++depth;
                continue;
            }
        }
        if (!found) {  // the sky, if any, MIS-weighted against its light samples like an emitter
            const Vec3 dir = normalize(rayDirection(ray));
            const Vec3 Le = lights_.environmentRadiance(dir);
            if (maxComponent(Le) > 0.0f) {
                const float weight = !specularBounce && settings_.lightSampling
                                         ? powerHeuristic(prevPdf, lights_.pdfEnvironment(dir))
                                         : 1.0f;
                L += beta * Le * weight;
            }
            break;
        }
        SurfacePoint s = surfaceAt(scene_, geometry_, ray, hit);
        Vec3 wo = -normalize(rayDirection(ray));
        if (s.material->interface) {
            // An invisible medium boundary: on in the same direction, in the medium beyond.
            medium = boundaries_.beyond(s.prim, -dot(s.ng, wo));
            segmentStart = hit.t;
            ray.tmin = hit.t + 1e-4f * std::max(1.0f, maxComponent(vmax(s.p, -s.p))) / pcl::length(rayDirection(ray));
            continue;
        }

        Vec3 Le = LightSampler::emitted(s, wo);
        if (maxComponent(Le) > 0.0f) {
            float weight = 1.0f;
            if (!specularBounce && settings_.lightSampling)
                weight = powerHeuristic(prevPdf, lights_.pdfLi(s.prim, prevP, s.p, s.ng));
            L += beta * Le * weight;
        }
        if (depth >= settings_.maxDepth) break;

        MixedBsdf bsdf(*s.material, s.rhoD, s.rhoS, s.exponent, s.ns, s.ng);
        if (bsdf.isBlack()) break;
        if (bsdf.hasNonDelta() && settings_.lightSampling)
            L += beta * sampleDirect(s, bsdf, wo, medium, sampler, vertex);

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
        segmentStart = 0.0f;
        // Through the surface (refraction): the medium on the other side.
        if (hasMedia_ && dot(s.ng, wo) * dot(s.ng, bs.wi) < 0.0f) medium = boundaries_.beyond(s.prim, dot(s.ng, bs.wi));

        // Russian roulette (Arvo & Kirk 1990): end with probability q, divide survivors by 1 - q.
        if (depth + 1 >= settings_.rouletteDepth) {
            float q = std::max(0.05f, 1.0f - maxComponent(beta) * rouletteScale);
            if (sampler.vertex(vertex, PathVertexDims::kRoulette) < q) break;
            beta *= 1.0f / (1.0f - q);
        }
        if (maxComponent(beta) <= 0.0f) break;
        ++depth;
    }
    return L;
}

CameraSample PathTracer::cameraSample(Sampler& sampler) {
    CameraSample cs;
    cs.filmX = sampler.get(CameraDims::kFilm);
    cs.filmY = sampler.get(CameraDims::kFilm + 1);
    cs.lensU = sampler.get(CameraDims::kLens);
    cs.lensV = sampler.get(CameraDims::kLens + 1);
    cs.time = sampler.get(CameraDims::kTime);
    return cs;
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
                        Vec3 L = Li(camera_.generateRay(x, y, cameraSample(sampler)), sampler);
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
