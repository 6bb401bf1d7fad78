#include "check/eye_stages.h"

#include <algorithm>

#include "check/on_device.h"
#include "core/clock.h"
#include "pipeline/camera_rays.h"
#include "pipeline/connect_caustics.h"
#include "pipeline/direct_light.h"
#include "pipeline/eye_paths.h"
#include "prep/area_light_table.h"
#include "reference/camera_rays.h"
#include "reference/connect_caustics.h"
#include "reference/direct_light.h"

namespace pcl {
namespace {

std::vector<float> segmentValues(const EyeVolumeSegments& s, const EyeVolumeSegments* twin, size_t records) {
    const size_t S = s.perRecord;
    std::vector<float> v;
    v.reserve(records * (S * 11 + 1));
    for (size_t i = 0; i < records; ++i) {
        const uint32_t count = i < s.counts.size() ? s.counts[i] : 0;
        bool same = true;
        for (size_t c = 0; c < S; ++c) {
            if (c < count) {
                const PclVolumeSegment& g = s.segments[c * records + i];
                v.insert(v.end(), {g.ox, g.oy, g.oz, g.length, g.dx, g.dy, g.dz, g.time, g.throughput[0],
                                   g.throughput[1], g.throughput[2]});
                if (twin) {
                    const PclVolumeSegment& t = twin->segments[c * records + i];
                    same = same && (c < twin->counts[i]) && g.medium == t.medium && g.record == t.record;
                }
            } else {
                v.insert(v.end(), 11, 0.0f);
            }
        }
        if (twin) same = same && count == twin->counts[i];
        v.push_back(same ? 1.0f : 0.0f);
    }
    return v;
}

RenderCheckReport makeReport(const RenderCheckOptions& o) {
    RenderCheckReport report;
    report.required = o.required;
    report.tolerance = o.tolerance;
    report.width = o.width;
    report.height = o.height;
    return report;
}

// The check's image: the scene's camera at the check's size.
Scene resized(const Scene& sceneIn, const RenderCheckOptions& o) {
    Scene scene = sceneIn;
    scene.camera.width = o.width;
    scene.camera.height = o.height;
    return scene;
}

}  // namespace

StageComparison compareEyeSegments(const EyeVolumeSegments& device, const EyeVolumeSegments& twin, double tolerance,
                                   size_t worstShown) {
    const size_t records = twin.counts.size();
    return compareValues("medium segments", segmentValues(device, &twin, records),
                         segmentValues(twin, nullptr, records), size_t(twin.perRecord) * 11 + 1, tolerance, worstShown);
}

RenderCheckReport checkEyePathsStage(Device& device, const Scene& sceneIn, const PreparedScene& prepared,
                                     const RenderCheckOptions& o) {
    RenderCheckReport report = makeReport(o);
    const Scene scene = resized(sceneIn, o);
    const AreaLightTable table = buildAreaLightTable(prepared.buffers, prepared.geometry.primitiveCount());
    const PclCameraParams cp = cameraParams(scene.camera, prepared.plan, eyePassSeed(o.seed, o.pass), o.strata);

    auto t0 = Clock::now();
    const std::vector<PclRay> dRays = cameraRaysOnDevice(device, cp);
    double dt = since(t0);
    t0 = Clock::now();
    StageComparison rays = compareRays(dRays, referenceCameraRays(scene.camera, cp), o.tolerance, o.worstShown);
    rays.deviceSeconds = dt;
    rays.twinSeconds = since(t0);
    report.stages.push_back(rays);

    const PclEyeParams ep = eyeParams(cp, prepared.geometry, prepared.buffers, table, o.maxDepth);
    EyeVolumeSegments dSeg, tSeg;
    t0 = Clock::now();
    const std::vector<PclEyeHit> dHits =
        eyePathsOnDevice(device, prepared.geometry, prepared.buffers, dRays, ep, &dSeg);
    dt = since(t0);
    t0 = Clock::now();
    const std::vector<PclEyeHit> tHits = referenceEyePaths(prepared.geometry, prepared.buffers, dRays, ep, &tSeg);
    const double twinSeconds = since(t0);
    StageComparison hits = compareEyeHits(dHits, tHits, o.tolerance, o.worstShown);
    hits.deviceSeconds = dt;
    hits.twinSeconds = twinSeconds;
    report.stages.push_back(hits);
    if (ep.volumeSegments > 0) report.stages.push_back(compareEyeSegments(dSeg, tSeg, o.tolerance, o.worstShown));
    return report;
}

RenderCheckReport checkDirectLightStage(Device& device, const Scene& sceneIn, const PreparedScene& prepared,
                                        const RenderCheckOptions& o) {
    RenderCheckReport report = makeReport(o);
    const Scene scene = resized(sceneIn, o);
    const AreaLightTable table = buildAreaLightTable(prepared.buffers, prepared.geometry.primitiveCount());
    const PclCameraParams cp = cameraParams(scene.camera, prepared.plan, eyePassSeed(o.seed, o.pass), o.strata);
    const std::vector<PclRay> rays = cameraRaysOnDevice(device, cp);
    const PclEyeParams ep = eyeParams(cp, prepared.geometry, prepared.buffers, table, o.maxDepth);
    const std::vector<PclEyeHit> hits = eyePathsOnDevice(device, prepared.geometry, prepared.buffers, rays, ep);
    // No gather in this check: light sampling alone (N = 0), weight 1.
    const PclDirectParams dp = directParams(ep, prepared.geometry, prepared.buffers, table, o.lightSamples, 0);
    auto t0 = Clock::now();
    const std::vector<PclRadiance> dDirect = directLightOnDevice(device, prepared.geometry, prepared.buffers, hits, dp);
    const double dt = since(t0);
    t0 = Clock::now();
    const std::vector<PclRadiance> tDirect = referenceDirectLight(prepared.geometry, prepared.buffers, hits, dp);
    StageComparison c = compareRadiance("direct light", dDirect, tDirect, o.tolerance, o.worstShown);
    c.deviceSeconds = dt;
    c.twinSeconds = since(t0);
    report.stages.push_back(c);
    return report;
}

// The splats summed per pixel (the film the render adds them to), as radiance samples.
std::vector<PclRadiance> splatFilm(const std::vector<PclSplat>& splats, size_t pixels) {
    std::vector<PclRadiance> film(pixels, PclRadiance{0, 0, 0, 0});
    for (const PclSplat& s : splats) {
        if (s.pixel == PCL_NO_SPLAT) continue;
        if (s.pixel >= pixels)
            throw InternalError("connect caustics: splat pixel " + std::to_string(s.pixel) + " outside the " +
                                std::to_string(pixels) + "-pixel film");
        film[s.pixel].r += s.r;
        film[s.pixel].g += s.g;
        film[s.pixel].b += s.b;
    }
    return film;
}

RenderCheckReport checkConnectCausticsStage(Device& device, const Scene& sceneIn, const PreparedScene& prepared,
                                            const RenderCheckOptions& o) {
    RenderCheckReport report = makeReport(o);
    const Scene scene = resized(sceneIn, o);
    // In a scene that moves, each record is connected at its photon's shutter time.
    const bool moves = prepared.plan.timeSampling;
    const PhotonMaps maps =
        photonMapsOnDevice(device, prepared.geometry, prepared.buffers, o.causticPhotons, o.seed, nullptr, moves);
    report.causticPhotons = maps.caustic.size();
    const uint64_t passSeed = eyePassSeed(o.seed, o.pass);
    PclCameraParams cp = cameraParams(scene.camera, prepared.plan, passSeed, o.strata);
    const PclConnectParams params =
        connectParams(prepared.geometry, prepared.buffers, uint32_t(maps.caustic.size()), passSeed, moves);
    auto t0 = Clock::now();
    DeviceScene dscene(device, prepared.geometry, prepared.buffers);
    const std::vector<PclSplat> d = connectCaustics(device, dscene, params, cp, maps.caustic, maps.causticTimes);
    const double dt = since(t0);
    t0 = Clock::now();
    const std::vector<PclSplat> t =
        referenceConnectCaustics(scene, prepared.geometry, params, cp, maps.caustic, maps.causticTimes);
    const double tt = since(t0);
    const size_t pixels = size_t(o.width) * o.height;
    // Per record: the pixel (1 where both name the same one or none) and the value.
    std::vector<float> dv, tv;
    for (size_t i = 0; i < t.size(); ++i) {
        const bool same = d[i].pixel == t[i].pixel;
        for (const PclSplat* s : {&d[i], &t[i]}) {
            std::vector<float>& v = s == &d[i] ? dv : tv;
            v.insert(v.end(), {s == &t[i] || same ? 1.0f : 0.0f, s->r, s->g, s->b});
        }
    }
    StageComparison records = compareValues("connections (pixel, rgb)", dv, tv, 4, o.tolerance, o.worstShown);
    records.deviceSeconds = dt;
    records.twinSeconds = tt;
    // A shadow ray grazing an occluder may end on either side: the kernel lifts it by the ray
    // epsilon along n_f, the twin by spawnShadowRay's relative offset (as for the film rows).
    records.ownRequired = o.filmRequired;
    report.stages.push_back(records);
    StageComparison film =
        compareRadiance("connection film", splatFilm(d, pixels), splatFilm(t, pixels), o.tolerance, o.worstShown);
    film.ownRequired = o.filmRequired;
    report.stages.push_back(film);
    return report;
}

}  // namespace pcl
