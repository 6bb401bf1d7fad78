#include "render/auto_method.h"

#include <algorithm>
#include <cstdio>

#include "core/clock.h"
#include "image/metrics.h"
#include "render/path_render.h"
#include "render/photon_renderer.h"

namespace pcl {
namespace {

constexpr int kPilotShrink = 4;         // the pilot renders width/4 × height/4
constexpr uint32_t kPilotSamples = 16;  // path tracer samples per pixel per pilot render

// The variance of one render: half the relMSE between two independent ones.
double renderVariance(const Image& a, const Image& b) { return 0.5 * compare(a, b).relMse; }

}  // namespace

std::string AutoMethodChoice::log() const {
    char line[320];
    std::snprintf(line, sizeof line,
                  "method auto: %s (pilot %.1f s: relMSE x seconds at full size fg %.3g (%.2f s a pass), path %.3g "
                  "(%.3f s a sample per pixel); fg's bias is not counted)\n",
                  renderMethodName(method), pilotSeconds, fgErrorSeconds, fgPassSeconds, pathErrorSeconds,
                  pathSampleSeconds);
    return line;
}

AutoMethodChoice chooseRenderMethod(Device& device, const Scene& scene, const PreparedScene& prepared,
                                    const RenderRequest& request) {
    const Clock::time_point start = Clock::now();
    const int width = scene.camera.width, height = scene.camera.height;
    Scene pilot = scene;
    pilot.camera.width = std::max(8, width / kPilotShrink);
    pilot.camera.height = std::max(8, height / kPilotShrink);
    const double pixelRatio = double(width) * height / (double(pilot.camera.width) * double(pilot.camera.height));
    AutoMethodChoice c;

    // fg: the full render's settings, one pass per seed.
    RenderRequest fgRequest = request;
    fgRequest.method = "fg";
    fgRequest.seconds = 0.0;
    fgRequest.passes = 1;
    PhotonRenderSettings s = resolveRenderSettings(fgRequest, prepared.plan, width, height).settings;
    s.photonBatch = planRenderMemory(device.info(), prepared.geometry, prepared.buffers, s, prepared.plan).photonBatch;
    Image fg[2];
    double fixed = 0, scaled = 0;
    for (int i = 0; i < 2; ++i) {
        s.seed = request.seed + 1000003 * (i + 1);
        const PhotonRenderResult r =
            renderPhotonMapped(device, pilot, prepared.geometry, prepared.buffers, prepared.plan, s);
        fg[i] = r.film.resolve();
        fixed += 0.5 * (r.times.photons + r.times.maps);
        scaled += 0.5 * (r.times.total - r.times.photons - r.times.maps);
    }
    c.fgPassSeconds = fixed + scaled * pixelRatio;
    c.fgErrorSeconds = renderVariance(fg[0], fg[1]) * c.fgPassSeconds;

    // The path tracer: kPilotSamples per pixel per seed.
    Image path[2];
    double pathSeconds = 0;
    for (int i = 0; i < 2; ++i) {
        PathRenderSettings p;
        p.seed = request.seed + 1000003 * (i + 1);
        p.samples = kPilotSamples;
        const PathRenderResult r = renderPathTraced(pilot, prepared.geometry, p);
        path[i] = r.film.resolve();
        pathSeconds += 0.5 * r.seconds;
    }
    c.pathSampleSeconds = pathSeconds / kPilotSamples * pixelRatio;
    c.pathErrorSeconds = renderVariance(path[0], path[1]) * pathSeconds * pixelRatio;

    c.method = c.fgErrorSeconds <= c.pathErrorSeconds ? RenderMethod::FinalGather : RenderMethod::PathTracing;
    c.pilotSeconds = since(start);
    return c;
}

}  // namespace pcl
