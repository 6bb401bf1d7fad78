#include "render/photon_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include "core/error.h"
#include "pipeline/camera_rays.h"
#include "pipeline/device_scene.h"
#include "pipeline/direct_light.h"
#include "pipeline/eye_estimate.h"
#include "pipeline/eye_paths.h"
#include "pipeline/final_gather.h"
#include "pipeline/irradiance_source.h"
#include "pipeline/photon_pass.h"
#include "pipeline/precomputed_irradiance.h"
#include "render/fixed_radius_source.h"

namespace pcl {

const char* renderMethodName(RenderMethod m) {
    switch (m) {
        case RenderMethod::FinalGather: return "fg";
        case RenderMethod::DirectVisualisation: return "direct";
        case RenderMethod::Progressive: return "progressive";
        case RenderMethod::PathTracing: return "path";
    }
    return "?";
}

RenderMethod parseRenderMethod(const std::string& name) {
    for (RenderMethod m : {RenderMethod::FinalGather, RenderMethod::DirectVisualisation, RenderMethod::Progressive,
                           RenderMethod::PathTracing})
        if (name == renderMethodName(m)) return m;
    throw InputError("render method '" + name + "': expected fg, direct, progressive or path");
}

RenderMaps mapsFor(RenderMethod method, const RenderPlan& plan) {
    RenderMaps maps;
    switch (method) {
        case RenderMethod::FinalGather:
            maps.global = plan.globalMap && plan.finalGather;
            maps.gather = maps.global;
            maps.caustic = plan.causticMap;
            break;
        case RenderMethod::DirectVisualisation:
            maps.global = true;  // the preview reads every kind of light from the global map
            break;
        case RenderMethod::Progressive:
            maps.global = plan.globalMap;
            maps.caustic = plan.causticMap;
            break;
        case RenderMethod::PathTracing: break;
    }
    return maps;
}

double sceneSurfaceArea(const Scene& scene) {
    double area = 0.0;
    for (const TriangleMesh& m : scene.meshes)
        for (size_t t = 0; t < m.triangleCount(); ++t) {
            Vec3 p0 = m.positions[m.indices[3 * t]], p1 = m.positions[m.indices[3 * t + 1]],
                 p2 = m.positions[m.indices[3 * t + 2]];
            area += 0.5 * length(cross(p1 - p0, p2 - p0));
        }
    for (const Sphere& s : scene.spheres) area += 4.0 * M_PI * double(s.radius) * s.radius;
    return area;
}

double progressiveRadius2(double r0Squared, double alpha, uint32_t pass) {
    double r2 = r0Squared;
    for (uint32_t i = 1; i <= pass; ++i) r2 *= (i + alpha) / (i + 1.0);  // r²_{i+1} = r²_i (i+α)/(i+1)
    return r2;
}

std::string StageTimes::table() const {
    struct Row {
        const char* name;
        double s;
    } rows[] = {{"photon pass", photons}, {"maps", maps},         {"camera", camera},       {"eye paths", eyePaths},
                {"direct light", direct}, {"caustics", caustic}, {"indirect", indirect}, {"accumulate", accumulate}};
    std::string out;
    char line[128];
    for (const Row& r : rows) {
        std::snprintf(line, sizeof line, "  %-13s %9.3f s  %5.1f %%\n", r.name, r.s, total > 0 ? 100.0 * r.s / total : 0.0);
        out += line;
    }
    std::snprintf(line, sizeof line, "  %-13s %9.3f s\n", "total", total);
    return out + line;
}

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Runs f, waits for the device, adds the wall time to `slot`.
template <class F>
void timed(Device& device, double& slot, F&& f) {
    auto t = Clock::now();
    f();
    device.finish();
    slot += since(t);
}

// The global map's photons that arrived after a diffuse bounce: what the progressive method
// reads at the eye hit, beside direct light by shadow rays (the photons straight from the
// lights, and those after specular bounces only, which the caustic map holds).
std::vector<PclPhoton> indirectPhotons(const std::vector<PclPhoton>& global) {
    std::vector<PclPhoton> out;
    out.reserve(global.size());
    for (const PclPhoton& p : global)
        if (p.packed & PCL_PHOTON_AFTER_DIFFUSE) out.push_back(p);
    return out;
}

bool finite(const PclRadiance& r) { return std::isfinite(r.r) && std::isfinite(r.g) && std::isfinite(r.b); }

}  // namespace

void applyRenderDefaults(PhotonRenderSettings& s, const RenderPlan& plan) {
    s.globalPhotons = plan.globalPhotons ? plan.globalPhotons : 200000;
    s.causticPhotons = plan.causticPhotons ? plan.causticPhotons : 100000;
    s.globalK = 50;
    s.causticK = 50;
    s.lightSamples = 16;
    const bool distributed = plan.lensSampling || plan.timeSampling || plan.glossySampling;
    switch (s.method) {
        case RenderMethod::FinalGather:
            // Gather rays carry the noise of the indirect part; strata × passes antialias and
            // add fresh photons. Lens, shutter and glossy lobes are sampled by the eye samples:
            // scenes that need them get 2×2 per pass and a quarter of the gather rays.
            s.strata = distributed ? 2 : 1;
            s.gatherRays = distributed ? 16 : 64;
            break;
        case RenderMethod::DirectVisualisation:
            s.gatherRays = 1;
            s.strata = 2;
            break;
        case RenderMethod::Progressive:
            s.gatherRays = 1;
            s.strata = 1;
            break;
        case RenderMethod::PathTracing: break;
    }
}

void applyRenderDefaults(PhotonRenderSettings& s, const RenderPlan& plan, const RenderOverrides& given) {
    applyRenderDefaults(s, plan);
    if (given.globalPhotons) s.globalPhotons = given.globalPhotons;
    if (given.causticPhotons) s.causticPhotons = given.causticPhotons;
    if (given.k) s.globalK = given.k;
    if (given.causticK) s.causticK = given.causticK;
    if (given.lightSamples) s.lightSamples = given.lightSamples;
    if (given.strata && s.method != RenderMethod::PathTracing) s.strata = given.strata;
    if (given.gatherRays && s.method == RenderMethod::FinalGather) s.gatherRays = given.gatherRays;
}

uint32_t defaultPasses(RenderMethod method, int width, int height) {
    const double megapixels = double(width) * height / 1e6;
    switch (method) {
        // One 256² pass with 64 gather rays takes ~2-6 s under PoCL on 2 cores.
        case RenderMethod::FinalGather: return uint32_t(std::clamp(int(10 * 0.065536 / std::max(megapixels, 1e-6) + 0.5), 1, 64));
        case RenderMethod::DirectVisualisation: return 4;  // a preview: seconds
        case RenderMethod::Progressive: return 32;
        case RenderMethod::PathTracing: break;
    }
    return 0;
}

PhotonRenderResult renderPhotonMapped(Device& device, const Scene& scene, const SceneGeometry& geometry,
                                      const SceneBuffers& buffers, const RenderPlan& plan,
                                      const PhotonRenderSettings& s) {
    if (s.method == RenderMethod::PathTracing)
        throw InputError("renderPhotonMapped: the path tracer is reference/path_tracer.h, not a photon method");
    if (s.strata < 1 || s.strata > 16) throw InputError("render: strata must be 1..16, got " + std::to_string(s.strata));
    if (s.gatherRays < 1) throw InputError("render: gather rays must be at least 1");
    if (s.globalK < 1 || s.globalK > PCL_KNN_MAX_K || s.causticK < 1 || s.causticK > PCL_KNN_MAX_K)
        throw InputError("render: k must be 1.." + std::to_string(PCL_KNN_MAX_K));
    if (!(s.alpha > 0.0f && s.alpha < 1.0f)) throw InputError("render: alpha must be in (0, 1)");
    if (s.passes == 0 && !(s.seconds > 0.0)) throw InputError("render: give a pass count or a time budget");

    auto start = Clock::now();
    const RenderMaps maps = mapsFor(s.method, plan);
    const int width = scene.camera.width, height = scene.camera.height;
    const uint32_t spp = s.strata * s.strata;
    const size_t passSamples = size_t(width) * height * spp;
    const uint32_t eyeDepth = s.eyeDepth ? s.eyeDepth : kDefaultEyeDepth;
    const bool fg = s.method == RenderMethod::FinalGather, progressive = s.method == RenderMethod::Progressive;
    const bool directVis = s.method == RenderMethod::DirectVisualisation;
    const Vec3 diag = geometry.bounds().extent();
    const float maxRadius = s.maxRadius > 0 ? s.maxRadius : 0.05f * length(diag);
    const uint32_t maxSpecularGather = kDefaultGatherSpecular;

    PhotonRenderResult result;
    result.sums = FixedPointFilm(width, height);
    if (s.aovs)
        result.aovs = {Film(width, height), Film(width, height), Film(width, height),
                       Film(width, height), Film(width, height), Film(width, height)};

    // Chunks of eye samples: the gather's per-ray buffers (32 bytes each, N per sample) and the
    // estimate's results within a quarter of the max allocation, at most 2^18 samples.
    size_t perSample = 32u * (fg ? s.gatherRays : 1u);
    size_t chunk = s.chunkSamples ? s.chunkSamples
                                  : std::clamp<size_t>(device.info().maxAlloc / 4 / perSample, 256, size_t(1) << 18);
    chunk = std::min(chunk, passSamples);
    result.chunkSamples = chunk;

    DeviceScene dscene(device, geometry, buffers);
    AreaLightTable table = buildAreaLightTable(buffers, geometry.primitiveCount());
    DeviceAreaLights lights(device, table);
    cl::Buffer rays = device.allocate<PclRay>(chunk, CL_MEM_READ_WRITE, "render: camera rays");
    cl::Buffer hits = device.allocate<PclEyeHit>(chunk, CL_MEM_READ_WRITE, "render: eye hits");
    cl::Buffer directRad = device.allocate<PclRadiance>(chunk, CL_MEM_READ_WRITE, "render: direct radiance");
    cl::Buffer causticRad = device.allocate<PclRadiance>(chunk, CL_MEM_READ_WRITE, "render: caustic radiance");
    cl::Buffer indirectRad = device.allocate<PclRadiance>(chunk, CL_MEM_READ_WRITE, "render: indirect radiance");

    EstimateSettings est;
    est.filter = progressive ? EstimateFilter::Box : s.filter;
    est.rayEpsilon = buffers.rayEpsilon;
    est.visibility = s.visibility;
    const double area = sceneSurfaceArea(scene);
    double r0Squared = s.initialRadius > 0 ? double(s.initialRadius) * s.initialRadius : 0.0;
    auto photonPass = [&](uint32_t pass) {
        PhotonPassOptions po;
        po.globalPhotons = s.globalPhotons;
        po.causticPhotons = s.causticPhotons;
        po.seed = s.seed;
        po.pass = pass;
        po.batchSize = s.photonBatch;
        po.buildGlobal = maps.global;
        po.buildCaustic = maps.caustic;
        return runPhotonPass(device, geometry, buffers, po);
    };
    // Progressive r_0: about progressiveK0 photons in the first disc at the mean density of
    // pass 0's stored global photons (caustic-only scenes: the caustic map's). A render that
    // starts later (a batch shard, firstPass > 0) traces pass 0's photons once to get the same
    // r_0, so r_0 never depends on which passes a shard holds.
    auto firstRadius2 = [&](const PhotonMaps& pass0) {
        double stored = maps.global ? pass0.global.size() : pass0.caustic.size();
        double lambda = std::max(stored, 1.0) / std::max(area, 1e-12);
        return std::min(double(maxRadius) * maxRadius, s.progressiveK0 / (M_PI * lambda));
    };
    if (progressive && r0Squared == 0.0 && s.firstPass > 0 && (maps.global || maps.caustic)) {
        timed(device, result.times.photons, [&] { r0Squared = firstRadius2(photonPass(0)); });
        result.firstRadius = static_cast<float>(std::sqrt(r0Squared));
    }

    {
        char line[512];
        std::snprintf(line, sizeof line,
                      "method %s, %u pass(es)%s, %u spp/pass, global %s, caustic %s, k %u/%u, %s%u gather rays%s, "
                      "%u light samples, r_max %.4g, %s%s, seed %llu",
                      renderMethodName(s.method), s.passes, s.seconds > 0 ? " or time budget" : "", spp,
                      maps.global ? std::to_string(s.globalPhotons).c_str() : "none",
                      maps.caustic ? std::to_string(s.causticPhotons).c_str() : "none", s.globalK, s.causticK,
                      fg ? (s.gatherSource == GatherSource::Precomputed && !s.visibility ? "precomputed irradiance, " : "full estimate, ")
                         : "",
                      fg ? s.gatherRays : 0u,
                      fg && s.histogramCells ? (" (importance " + std::to_string(s.histogramCells) + "x" +
                                                std::to_string(s.histogramCells) + ")").c_str()
                                             : "",
                      s.lightSamples, maxRadius, knnStructureName(s.structure), s.visibility ? ", visibility test" : "",
                      static_cast<unsigned long long>(s.seed));
        result.summary = line;
    }

    Film passFilm;
    for (uint32_t done = 0;; ++done) {
        if (s.passes && done >= s.passes) break;
        if (done > 0 && s.seconds > 0 && since(start) >= s.seconds) break;
        if (done > 0 && s.stop && s.stop->load()) {
            result.stopped = true;
            break;
        }
        const uint32_t pass = s.firstPass + done;  // the global pass index: in every seed
        passFilm = Film(width, height);
        // 1. Photons: a fresh pass (the pass index in its seed).
        PhotonMaps photons;
        if (maps.global || maps.caustic) {
            timed(device, result.times.photons, [&] { photons = photonPass(pass); });
            result.globalEmitted += photons.stats.global.emitted;
            result.causticEmitted += photons.stats.caustic.emitted;
            result.globalStored += photons.global.size();
            result.causticStored += photons.caustic.size();
        }
        // 2. Maps and the irradiance sources that read them.
        std::unique_ptr<PhotonMapOnDevice> globalMap, causticMap, histogramMap;
        std::unique_ptr<DeviceIrradianceMap> irradiance;
        std::shared_ptr<IrradianceSource> globalSource, causticSource;
        float radius2 = maxRadius * maxRadius;
        if (progressive) {
            if (r0Squared == 0.0) {  // pass 0 (firstPass > 0 computed it above)
                r0Squared = firstRadius2(photons);
                result.firstRadius = static_cast<float>(std::sqrt(r0Squared));
            }
            radius2 = static_cast<float>(progressiveRadius2(r0Squared, s.alpha, pass));
            result.lastRadius = std::sqrt(radius2);
        }
        timed(device, result.times.maps, [&] {
            float searchRadius = std::sqrt(radius2);
            if (maps.global && !photons.global.empty()) {
                if (progressive) {
                    std::vector<PclPhoton> indirect = indirectPhotons(photons.global);
                    if (!indirect.empty()) {
                        globalMap = std::make_unique<PhotonMapOnDevice>(device, indirect, s.structure,
                                                                        searchRadius);
                        globalSource = fixedRadiusSource(*globalMap, PCL_KNN_MAX_K, est, radius2, &dscene);
                    }
                } else if (fg && s.gatherSource == GatherSource::Precomputed && !s.visibility) {
                    // (With visibility the full estimate is read instead: a precomputed record is
                    // found by one nearest lookup with no visibility test, so a record across a
                    // thin wall would be read: the stability suite's thin-wall test.)
                    PrecomputedIrradianceOptions po;
                    po.k = s.globalK;
                    po.maxRadius = maxRadius;
                    po.estimate = est;
                    irradiance = std::make_unique<DeviceIrradianceMap>(
                        precomputeIrradiance(device, photons.global, po, &dscene));
                    globalSource = precomputedIrradianceSource(*irradiance);
                } else {
                    globalMap = std::make_unique<PhotonMapOnDevice>(device, photons.global, s.structure,
                                                                    searchRadius);
                    globalSource = estimateIrradianceSource(*globalMap, s.globalK, est, &dscene);
                }
            }
            if (fg && s.histogramCells > 0 && globalSource) {
                // The importance histograms read the global map's k nearest photons directly.
                histogramMap = std::make_unique<PhotonMapOnDevice>(device, photons.global, s.structure,
                                                                   searchRadius);
            }
            if (maps.caustic && !photons.caustic.empty()) {
                causticMap = std::make_unique<PhotonMapOnDevice>(device, photons.caustic, s.structure,
                                                                 searchRadius);
                causticSource = progressive ? fixedRadiusSource(*causticMap, PCL_KNN_MAX_K, est, radius2, &dscene)
                                            : estimateIrradianceSource(*causticMap, s.causticK, est, &dscene);
            }
        });
        // 3. Eye samples, chunk by chunk.
        const uint64_t passSeed = eyePassSeed(s.seed, pass);
        for (size_t first = 0; first < passSamples; first += chunk) {
            const uint32_t count = static_cast<uint32_t>(std::min(chunk, passSamples - first));
            PclCameraParams cp = cameraParams(scene.camera, plan, passSeed, s.strata);
            cp.firstSample = static_cast<uint32_t>(first);
            cp.sampleCount = count;
            timed(device, result.times.camera, [&] { generateCameraRays(device, cp, rays); });
            PclEyeParams ep = eyeParams(cp, geometry, buffers, eyeDepth);
            timed(device, result.times.eyePaths, [&] { traceEyePaths(device, dscene, ep, rays, hits); });
            const PclRadiance zero{0, 0, 0, 0};
            bool haveDirect = false, haveCaustic = false, haveIndirect = false;
            const bool gather = fg && globalSource;
            PclDirectParams dp = directParams(ep, geometry, buffers, table, s.lightSamples, gather ? s.gatherRays : 0u);
            PclGatherParams gp{};
            cl::Buffer histograms;
            if (gather) {
                gp = gatherParams(dp, s.gatherRays, s.globalK, maxRadius * maxRadius, maxSpecularGather);
                gp.causticMapRead = maps.caustic ? 1u : 0u;
                if (histogramMap) {
                    gp.histogramCells = dp.histogramCells = s.histogramCells;
                    timed(device, result.times.indirect,
                          [&] { histograms = buildGatherHistograms(device, *histogramMap, gp, hits); });
                }
            }
            if (!directVis) {
                timed(device, result.times.direct, [&] {
                    if (histogramMap) directLight(device, dscene, lights, dp, hits, histograms, directRad);
                    else directLight(device, dscene, lights, dp, hits, directRad);
                });
                haveDirect = true;
            }
            if (causticSource) {
                PclEyeEstimateParams cq{count, progressive ? PCL_KNN_MAX_K : s.causticK, radius2, 0};
                timed(device, result.times.caustic,
                      [&] { causticRadiance(device, cq, hits, *causticSource, causticRad); });
                haveCaustic = true;
            }
            if (globalSource) {
                timed(device, result.times.indirect, [&] {
                    if (fg) {
                        if (histogramMap) finalGather(device, dscene, lights, gp, hits, histograms, *globalSource, indirectRad);
                        else finalGather(device, dscene, lights, gp, hits, *globalSource, indirectRad);
                    } else {
                        PclEyeEstimateParams gq{count, progressive ? PCL_KNN_MAX_K : s.globalK, radius2, 0};
                        estimateAtEyeHits(device, gq, hits, *globalSource, indirectRad);
                    }
                });
                haveIndirect = true;
            }
            // 4. Accumulate: sample s of the pass lies in pixel s / n².
            auto t = Clock::now();
            std::vector<PclEyeHit> eye = device.download<PclEyeHit>(hits, count);
            auto part = [&](bool have, cl::Buffer& b) {
                return have ? device.download<PclRadiance>(b, count) : std::vector<PclRadiance>(count, zero);
            };
            std::vector<PclRadiance> direct = part(haveDirect, directRad), caustic = part(haveCaustic, causticRad),
                                     indirect = part(haveIndirect, indirectRad);
            for (uint32_t i = 0; i < count; ++i) {
                size_t pixel = (first + i) / spp;
                int x = static_cast<int>(pixel % width), y = static_cast<int>(pixel / width);
                const PclEyeHit& h = eye[i];
                PclRadiance em{h.emitted[0], h.emitted[1], h.emitted[2], 0};
                PclRadiance sum{em.r + direct[i].r + caustic[i].r + indirect[i].r,
                                em.g + direct[i].g + caustic[i].g + indirect[i].g,
                                em.b + direct[i].b + caustic[i].b + indirect[i].b, 0};
                if (!finite(sum)) {
                    ++result.nonFiniteSamples;
                    sum = zero;  // counted and reported; the pixel keeps its weight
                }
                passFilm.add(x, y, {sum.r, sum.g, sum.b});
                if (s.aovs) {
                    auto v = [](const PclRadiance& r) { return finite(r) ? Vec3(r.r, r.g, r.b) : Vec3(0.0f); };
                    result.aovs.direct.add(x, y, v(direct[i]));
                    result.aovs.caustic.add(x, y, v(caustic[i]));
                    result.aovs.indirect.add(x, y, v(indirect[i]));
                    result.aovs.emitted.add(x, y, v(em));
                    bool diffuse = h.flags & PCL_EYE_DIFFUSE;
                    result.aovs.albedo.add(x, y, diffuse ? Vec3(h.albedo[0], h.albedo[1], h.albedo[2]) : Vec3(0.0f));
                    result.aovs.normal.add(x, y, diffuse ? Vec3(h.nx, h.ny, h.nz) : Vec3(0.0f));
                }
            }
            result.times.accumulate += since(t);
            result.samples += count;
        }
        // 5. The pass's sums, rounded once to fixed point, join the render's (exact: any
        // grouping of passes gives the same bits).
        {
            auto t = Clock::now();
            result.sums.addPass(passFilm);
            result.times.accumulate += since(t);
        }
        result.passes = done + 1;
        double fraction = s.passes ? double(result.passes) / s.passes : 0.0;
        if (s.seconds > 0) fraction = std::max(fraction, std::min(1.0, since(start) / s.seconds));
        if (s.log)
            std::fprintf(stderr, "pass %u: %zu global + %zu caustic photons stored%s\n", pass, photons.global.size(),
                         photons.caustic.size(),
                         progressive ? (", radius " + std::to_string(std::sqrt(radius2))).c_str() : "");
        if (s.onPass) s.onPass(result.passes, std::min(1.0, fraction));
    }
    if (!result.stopped && s.stop && s.stop->load() && s.passes && result.passes < s.passes) result.stopped = true;
    passFilm = Film();  // (host memory: a 4K film is 265 MB)
    result.film = result.sums.toFilm();
    result.times.total = since(start);
    return result;
}

}  // namespace pcl
