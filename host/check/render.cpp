#include "check/render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/clock.h"
#include "geometry/scene_geometry.h"
#include "pipeline/camera_rays.h"
#include "pipeline/direct_light.h"
#include "pipeline/eye_estimate.h"
#include "pipeline/eye_paths.h"
#include "pipeline/final_gather.h"
#include "pipeline/irradiance_source.h"
#include "pipeline/photon_pass.h"
#include "pipeline/precomputed_irradiance.h"
#include "prep/plan.h"
#include "prep/projection_map.h"
#include "prep/scene_buffers.h"
#include "reference/camera_rays.h"
#include "reference/direct_light.h"
#include "reference/eye_estimate.h"
#include "reference/eye_paths.h"
#include "reference/final_gather.h"
#include "reference/precomputed_irradiance.h"
#include "render/device_stages.h"
#include "render/photon_renderer.h"
#include "render/shared_photons.h"
#include "render/twin_stages.h"

namespace pcl {
namespace {

// The film rows' render: one pass (the check's) at the check's sizes, seeds and radius.
PhotonRenderSettings filmSettings(const RenderCheckOptions& o, RenderMethod method, float rMax) {
    PhotonRenderSettings s;
    s.method = method;
    s.strata = o.strata;
    s.globalPhotons = o.globalPhotons;
    s.causticPhotons = o.causticPhotons;
    s.globalK = s.causticK = o.k;
    s.gatherRays = o.gatherRays;
    s.lightSamples = o.lightSamples;
    s.eyeDepth = o.maxDepth;
    s.maxRadius = rMax;
    s.filter = o.estimate.filter;
    s.histogramCells = method == RenderMethod::FinalGather ? o.histogramCells : 0;
    s.seed = o.seed;
    s.firstPass = o.pass;
    s.passes = 1;
    return s;
}

std::vector<float> radianceFloats(const std::vector<PclRadiance>& r) {
    std::vector<float> v;
    v.reserve(r.size() * 3);
    for (const PclRadiance& x : r) v.insert(v.end(), {x.r, x.g, x.b});
    return v;
}

}  // namespace

StageComparison compareValues(const std::string& stage, const std::vector<float>& device,
                              const std::vector<float>& twin, size_t values, double tolerance, size_t worstShown) {
    StageComparison c;
    c.stage = stage;
    const size_t n = std::min(device.size(), twin.size()) / std::max<size_t>(values, 1);
    double peak = 0.0;
    for (float t : twin)
        if (std::isfinite(t)) peak = std::max(peak, double(std::fabs(t)));
    const double floor = 1e-6 * peak;
    std::vector<WorstSample> all;
    for (size_t i = 0; i < n; ++i) {
        bool finite = true, nonzero = false;
        double worst = 0.0;
        bool ok = true;
        for (size_t v = 0; v < values; ++v) {
            const double d = device[i * values + v], t = twin[i * values + v];
            if (!std::isfinite(d) || !std::isfinite(t)) {
                finite = false;
                continue;
            }
            nonzero = nonzero || t != 0.0;
            const double diff = std::fabs(d - t), scale = std::max(std::fabs(d), std::fabs(t));
            if (diff > tolerance * scale + floor) ok = false;
            if (scale > 0.0 && diff > floor) worst = std::max(worst, diff / scale);
        }
        ++c.compared;
        if (!finite) ++c.nonFinite;
        if (nonzero) ++c.nonzero;
        if (ok && finite) ++c.matched;
        c.maxRelError = std::max(c.maxRelError, worst);
        if (worst > 0.0 && worstShown > 0) {
            WorstSample w;
            w.index = i;
            w.relError = worst;
            for (size_t v = 0; v < std::min<size_t>(values, 3); ++v) {
                w.device[v] = device[i * values + v];
                w.twin[v] = twin[i * values + v];
            }
            all.push_back(w);
        }
    }
    std::sort(all.begin(), all.end(), [](const WorstSample& a, const WorstSample& b) {
        return a.relError > b.relError || (a.relError == b.relError && a.index < b.index);
    });
    if (all.size() > worstShown) all.resize(worstShown);
    c.worst = std::move(all);
    return c;
}

StageComparison compareRadiance(const std::string& stage, const std::vector<PclRadiance>& device,
                                const std::vector<PclRadiance>& twin, double tolerance, size_t worstShown) {
    return compareValues(stage, radianceFloats(device), radianceFloats(twin), 3, tolerance, worstShown);
}

StageComparison compareRays(const std::vector<PclRay>& device, const std::vector<PclRay>& twin, double tolerance,
                            size_t worstShown) {
    auto flat = [](const std::vector<PclRay>& rays) {
        std::vector<float> v;
        for (const PclRay& r : rays) v.insert(v.end(), {r.dx, r.dy, r.dz, r.ox, r.oy, r.oz, r.time});
        return v;
    };
    return compareValues("camera rays", flat(device), flat(twin), 7, tolerance, worstShown);
}

StageComparison compareEyeHits(const std::vector<PclEyeHit>& device, const std::vector<PclEyeHit>& twin,
                               double tolerance, size_t worstShown) {
    // Values: throughput, position, normal, emitted, albedo (ρd at the hit: textured), shading
    // normal (smooth meshes), then a
    // 0/1 "same flags, prim, pixel, sample" value (twin 1, device 1 when equal, else 0: a
    // mismatch of 100 %).
    auto flat = [&](const std::vector<PclEyeHit>& hits, bool isDevice) {
        std::vector<float> v;
        for (size_t i = 0; i < hits.size(); ++i) {
            const PclEyeHit& h = hits[i];
            v.insert(v.end(),
                     {h.throughput[0], h.throughput[1], h.throughput[2], h.x, h.y, h.z, h.nx, h.ny, h.nz, h.emitted[0],
                      h.emitted[1], h.emitted[2], h.albedo[0], h.albedo[1], h.albedo[2], h.snx, h.sny, h.snz});
            float same = 1.0f;
            if (isDevice && i < twin.size()) {
                const PclEyeHit& t = twin[i];
                same = (h.flags == t.flags && h.prim == t.prim && h.pixel == t.pixel && h.sample == t.sample &&
                        h.material == t.material && h.depth == t.depth)
                           ? 1.0f
                           : 0.0f;
            }
            v.push_back(same);
        }
        return v;
    };
    return compareValues("eye paths", flat(device, true), flat(twin, false), 19, tolerance, worstShown);
}

bool RenderCheckReport::passed() const {
    if (stages.empty()) return false;
    for (const StageComparison& s : stages)
        if (!s.passed(required)) return false;
    return true;
}

std::string RenderCheckReport::table() const {
    std::ostringstream o;
    char line[512];
    std::snprintf(line, sizeof line, "render check: %dx%d, %zu global / %zu caustic photons\n", width, height,
                  globalPhotons, causticPhotons);
    o << line;
    std::snprintf(line, sizeof line, "%-24s %9s %9s %10s %9s %12s %9s %9s  %s\n", "stage", "samples", "nonzero",
                  "match %", "NaN/Inf", "max rel", "device s", "twin s", "result");
    o << line;
    for (const StageComparison& s : stages) {
        std::snprintf(line, sizeof line, "%-24s %9zu %9zu %10.4f %9zu %12.3e %9.3f %9.3f  %s\n", s.stage.c_str(),
                      s.compared, s.nonzero, 100.0 * s.fraction(), s.nonFinite, s.maxRelError, s.deviceSeconds,
                      s.twinSeconds, s.passed(required) ? "ok" : "FAILED");
        o << line;
    }
    for (const StageComparison& s : stages)
        for (const WorstSample& w : s.worst) {
            std::snprintf(line, sizeof line,
                          "  worst %-16s #%-8zu rel %.3e  device (%.6g, %.6g, %.6g)  twin (%.6g, %.6g, %.6g)\n",
                          s.stage.c_str(), w.index, w.relError, w.device[0], w.device[1], w.device[2], w.twin[0],
                          w.twin[1], w.twin[2]);
            o << line;
        }
    std::snprintf(line, sizeof line,
                  "a value matches when |d - t| <= %.0e max(|d|, |t|) + 1e-6 peak; a stage passes with >= %.2f %% of "
                  "its samples matching and no NaN/Inf",
                  tolerance, 100.0 * required);
    o << line;
    for (const StageComparison& s : stages)
        if (s.ownRequired > 0.0) {
            std::snprintf(line, sizeof line, " (the films: >= %.2f %% of their pixels)", 100.0 * s.ownRequired);
            o << line;
            break;
        }
    o << "\n";
    return o.str();
}

RenderCheckReport checkRender(Device& device, const Scene& scene, const RenderCheckOptions& options) {
    return checkRender(device, scene, prepareScene(scene), options);
}

RenderCheckReport checkRender(Device& device, const Scene& sceneIn, const PreparedScene& prepared,
                              const RenderCheckOptions& o) {
    RenderCheckReport report;
    report.required = o.required;
    report.tolerance = o.tolerance;
    Scene scene = sceneIn;
    scene.camera.width = o.width;
    scene.camera.height = o.height;
    report.width = o.width;
    report.height = o.height;
    // (The image size changes neither the geometry, the buffers nor the plan.)
    const SceneGeometry& geometry = prepared.geometry;
    const SceneBuffers& buffers = prepared.buffers;
    const RenderPlan& plan = prepared.plan;
    const DeviceScene deviceScene(device, geometry, buffers);
    const AreaLightTable table = buildAreaLightTable(buffers, geometry.primitiveCount());
    const DeviceAreaLights deviceLights(device, table);

    PhotonPassOptions po;
    po.globalPhotons = o.globalPhotons;
    po.causticPhotons = o.causticPhotons;
    po.seed = o.seed;
    po.pass = o.pass;
    const PhotonMaps maps = runPhotonPass(device, geometry, buffers, po);
    report.globalPhotons = maps.global.size();
    report.causticPhotons = maps.caustic.size();
    const Vec3 ext = geometry.bounds().extent();
    const float rMax = std::max(o.radiusFraction * std::sqrt(dot(ext, ext)), 1e-6f);
    EstimateSettings es = o.estimate;
    es.rayEpsilon = buffers.rayEpsilon;

    auto timed = [&](StageComparison c, double dev, double twin) {
        c.deviceSeconds = dev;
        c.twinSeconds = twin;
        report.stages.push_back(std::move(c));
    };
    auto deviceSeconds = [&](cl::Event e) {
        device.finish();
        return e() ? Device::elapsedSeconds(e) : 0.0;
    };

    // 1. Camera.
    const PclCameraParams cp = cameraParams(scene.camera, plan, eyePassSeed(o.seed, o.pass), o.strata);
    const size_t n = cp.sampleCount;
    cl::Buffer rays = device.allocate<PclRay>(n, CL_MEM_READ_WRITE, "check render: rays");
    double dt = deviceSeconds(generateCameraRays(device, cp, rays));
    const std::vector<PclRay> dRays = device.download<PclRay>(rays, n);
    auto t0 = Clock::now();
    const std::vector<PclRay> tRays = referenceCameraRays(scene.camera, cp);
    timed(compareRays(dRays, tRays, o.tolerance, o.worstShown), dt, since(t0));

    // 2. Eye paths from the device rays.
    const PclEyeParams ep = eyeParams(cp, geometry, buffers, table, o.maxDepth);
    cl::Buffer hits = device.allocate<PclEyeHit>(n, CL_MEM_READ_WRITE, "check render: eye hits");
    dt = deviceSeconds(traceEyePaths(device, deviceScene, deviceLights, ep, rays, hits));
    const std::vector<PclEyeHit> dHits = device.download<PclEyeHit>(hits, n);
    t0 = Clock::now();
    const std::vector<PclEyeHit> tHits = referenceEyePaths(geometry, buffers, dRays, ep);
    timed(compareEyeHits(dHits, tHits, o.tolerance, o.worstShown), dt, since(t0));

    std::vector<PclRadiance> emitted(n);
    for (size_t i = 0; i < n; ++i) emitted[i] = {dHits[i].emitted[0], dHits[i].emitted[1], dHits[i].emitted[2], 0.0f};

    // 3. Direct light from the device records.
    const PclDirectParams dp = directParams(ep, geometry, buffers, table, o.lightSamples, o.gatherRays);
    cl::Buffer direct = device.allocate<PclRadiance>(n, CL_MEM_READ_WRITE, "check render: direct");
    dt = deviceSeconds(directLight(device, deviceScene, deviceLights, dp, hits, direct));
    const std::vector<PclRadiance> dDirect = device.download<PclRadiance>(direct, n);
    t0 = Clock::now();
    std::vector<PclRadiance> tDirect(n);
    for (size_t i = 0; i < n; ++i) tDirect[i] = referenceDirectLightAt(geometry, buffers, table, dp, dHits[i]);
    timed(compareRadiance("direct light", dDirect, tDirect, o.tolerance, o.worstShown), dt, since(t0));

    // 4. Final gather on the global map.
    std::vector<PclRadiance> dGather(n), tGather(n);
    if (!maps.global.empty() && o.gatherRays > 0) {
        PhotonMapOnDevice global(device, maps.global, KnnStructure::KdTree, rMax);
        auto source = estimateIrradianceSource(global, o.k, es, &deviceScene);
        PclGatherParams gp = gatherParams(dp, o.gatherRays, o.k, rMax * rMax);
        gp.causticMapRead = maps.caustic.empty() ? 0u : 1u;  // as the renderer: LS+D left to the caustic map
        gp.causticSky = skySendsCausticPhotons(buffers) ? 1u : 0u;
        // Gather hits within r_max take their direct light by shadow rays and the map's other
        // photons (the renderer's --close-gather reaches a few r_k): both halves checked.
        gp.closeDistance = rMax;
        cl::Buffer gathered = device.allocate<PclRadiance>(n, CL_MEM_READ_WRITE, "check render: gather");
        const GatherTiming gt = finalGather(device, deviceScene, deviceLights, gp, hits, *source, gathered);
        dGather = device.download<PclRadiance>(gathered, n);
        t0 = Clock::now();
        tGather =
            referenceFinalGather(geometry, buffers, dHits, gp, referenceEstimateIrradiance(maps.global, es, &geometry))
                .radiance;
        timed(compareRadiance("final gather", dGather, tGather, o.tolerance, o.worstShown),
              gt.traceSeconds + gt.irradianceSeconds + gt.resolveSeconds, since(t0));

        // The same gather reading precomputed irradiance (the renderer's default): the twin
        // looks up the device's stored points by brute force (the points themselves are
        // checkIrradiance's business).
        PrecomputedIrradianceOptions pio;
        pio.maxRadius = rMax;
        pio.k = o.k;
        pio.estimate = es;
        const DeviceIrradianceMap irr = precomputeIrradiance(device, maps.global, pio, &deviceScene);
        auto pre = precomputedIrradianceSource(irr);
        const GatherTiming pt = finalGather(device, deviceScene, deviceLights, gp, hits, *pre, gathered);
        const std::vector<PclRadiance> dPre = device.download<PclRadiance>(gathered, n);
        const std::vector<PclIrradiancePoint> points = downloadIrradiancePoints(device, irr);
        const std::vector<float> cover = downloadIrradianceCover(device, irr);
        const std::vector<float> nondirect = downloadIrradianceNondirect(device, irr);
        t0 = Clock::now();
        const std::vector<PclRadiance> tPre =
            referenceFinalGather(geometry, buffers, dHits, gp,
                                 referencePrecomputedIrradiance(points, cover, irr.minNormalCos, nondirect))
                .radiance;
        timed(compareRadiance("final gather (precomp.)", dPre, tPre, o.tolerance, o.worstShown),
              pt.traceSeconds + pt.irradianceSeconds + pt.resolveSeconds, since(t0));

        if (o.histogramCells > 0) {
            PclGatherParams ip = gp;
            ip.histogramCells = o.histogramCells;
            PclDirectParams idp = dp;
            idp.histogramCells = o.histogramCells;
            auto t1 = Clock::now();
            const cl::Buffer hist = buildGatherHistograms(device, global, ip, hits);
            const double histSeconds = since(t1);
            const size_t C = size_t(o.histogramCells) * o.histogramCells;
            const std::vector<float> dHist = device.download<float>(hist, n * C);
            t0 = Clock::now();
            const std::vector<float> tHist = referenceGatherHistograms(maps.global, dHits, ip);
            timed(compareValues("importance histograms", dHist, tHist, C, o.tolerance, o.worstShown), histSeconds,
                  since(t0));
            const GatherTiming it = finalGather(device, deviceScene, deviceLights, ip, hits, hist, *pre, gathered);
            const std::vector<PclRadiance> dImp = device.download<PclRadiance>(gathered, n);
            t0 = Clock::now();
            const std::vector<PclRadiance> tImp =
                referenceFinalGather(geometry, buffers, dHits, ip,
                                     referencePrecomputedIrradiance(points, cover, irr.minNormalCos, nondirect), &dHist)
                    .radiance;
            timed(compareRadiance("final gather (import.)", dImp, tImp, o.tolerance, o.worstShown),
                  it.traceSeconds + it.irradianceSeconds + it.resolveSeconds, since(t0));
            cl::Buffer impDirect = device.allocate<PclRadiance>(n, CL_MEM_READ_WRITE, "check render: direct (import.)");
            const double ds = deviceSeconds(directLight(device, deviceScene, deviceLights, idp, hits, hist, impDirect));
            const std::vector<PclRadiance> dID = device.download<PclRadiance>(impDirect, n);
            t0 = Clock::now();
            std::vector<PclRadiance> tID(n);
            for (size_t i = 0; i < n; ++i)
                tID[i] = referenceDirectLightAt(geometry, buffers, table, idp, dHits[i], dHist.data() + i * C);
            timed(compareRadiance("direct light (import.)", dID, tID, o.tolerance, o.worstShown), ds, since(t0));
        }
    }

    // 5. Caustics and direct visualisation.
    PclEyeEstimateParams pe{};
    pe.sampleCount = uint32_t(n);
    pe.k = o.k;
    pe.maxRadius2 = rMax * rMax;
    std::vector<PclRadiance> dCaustic(n), tCaustic(n);
    for (int which = 0; which < 2; ++which) {
        const std::vector<PclPhoton>& map = which == 0 ? maps.caustic : maps.global;
        if (map.empty()) continue;
        pe.atShutterOpen = which == 1 ? 1u : 0u;  // the global map's moving surfaces (shutter_open.h)
        PhotonMapOnDevice m(device, map, KnnStructure::KdTree, rMax);
        auto source = estimateIrradianceSource(m, o.k, es, &deviceScene);
        cl::Buffer out = device.allocate<PclRadiance>(n, CL_MEM_READ_WRITE, "check render: estimate at eye hits");
        dt = estimateAtEyeHits(device, pe, hits, deviceScene.primInfo, *source, out);
        std::vector<PclRadiance> d = device.download<PclRadiance>(out, n);
        t0 = Clock::now();
        std::vector<PclRadiance> t =
            referenceEstimateAtEyeHits(dHits, pe, buffers.primInfo, referenceEstimateIrradiance(map, es, &geometry));
        timed(compareRadiance(which == 0 ? "caustics" : "direct visualisation", d, t, o.tolerance, o.worstShown), dt,
              since(t0));
        if (which == 0) {
            dCaustic = std::move(d);
            tCaustic = std::move(t);
        }
    }

    // 6. Per pixel: emitted + direct + caustics + gather, averaged over the pixel's samples.
    const size_t pixels = size_t(o.width) * o.height, spp = size_t(o.strata) * o.strata;
    std::vector<float> dPix(pixels * 3, 0.0f), tPix(pixels * 3, 0.0f);
    for (size_t i = 0; i < n; ++i) {
        const size_t px = dHits[i].pixel;
        const float d[3] = {emitted[i].r + dDirect[i].r + dCaustic[i].r + dGather[i].r,
                            emitted[i].g + dDirect[i].g + dCaustic[i].g + dGather[i].g,
                            emitted[i].b + dDirect[i].b + dCaustic[i].b + dGather[i].b};
        const float t[3] = {tHits[i].emitted[0] + tDirect[i].r + tCaustic[i].r + tGather[i].r,
                            tHits[i].emitted[1] + tDirect[i].g + tCaustic[i].g + tGather[i].g,
                            tHits[i].emitted[2] + tDirect[i].b + tCaustic[i].b + tGather[i].b};
        for (int c = 0; c < 3; ++c) {
            dPix[px * 3 + c] += d[c] / float(spp);
            tPix[px * 3 + c] += t[c] / float(spp);
        }
    }
    timed(compareValues("pixels", dPix, tPix, 3, o.tolerance, o.worstShown), 0.0, 0.0);

    // 7. The films: the renderer on the device and on the twin, the twin given the device's photons.
    if (o.films)
        for (RenderMethod m :
             {RenderMethod::FinalGather, RenderMethod::DirectVisualisation, RenderMethod::Progressive}) {
            const PhotonRenderSettings s = filmSettings(o, m, rMax);
            PhotonPassRecord photons;
            t0 = Clock::now();
            Image dFilm;
            {
                DeviceRenderStages stages(device, scene, geometry, buffers, s);
                SharedPhotonStages recording(stages, photons, SharedPhotonStages::Mode::Record);
                dFilm = renderPhotonMapped(recording, scene, geometry, buffers, plan, s).film.resolve();
            }
            dt = since(t0);
            t0 = Clock::now();
            TwinRenderStages stages(scene, geometry, buffers);
            SharedPhotonStages replaying(stages, photons, SharedPhotonStages::Mode::Replay);
            const Image tFilm = renderPhotonMapped(replaying, scene, geometry, buffers, plan, s).film.resolve();
            StageComparison c = compareValues(std::string("film ") + renderMethodName(m), dFilm.rgb, tFilm.rgb, 3,
                                              o.tolerance, o.worstShown);
            c.ownRequired = o.filmRequired;
            timed(std::move(c), dt, since(t0));
        }
    return report;
}

}  // namespace pcl
