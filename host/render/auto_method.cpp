#include "render/auto_method.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/clock.h"
#include "image/metrics.h"
#include "render/path_render.h"
#include "render/photon_renderer.h"

namespace pcl {
namespace {

constexpr int kPilotShrink = 4;         // the pilot renders width/4 × height/4 …
constexpr int kPilotMinWidth = 64;      // … and at least this wide (the whole image if narrower)
constexpr uint32_t kPilotSamples = 16;  // path tracer samples per pixel per pilot render
constexpr int kPathPilotRenders = 6;    // the path tracer's pilot renders: its fireflies need more than
                                        // two for a steady variance (fg's passes are dearer: two)

// The relative variance of one render from K ≥ 2 independent ones: per pixel and channel the
// sample variance over the K over (mean² + ε) (relMSE's ε), averaged.
double renderVariance(const std::vector<Image>& runs) {
    const size_t K = runs.size(), n = runs.front().rgb.size();
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double mean = 0.0, sq = 0.0;
        for (const Image& r : runs) mean += r.rgb[i];
        mean /= double(K);
        for (const Image& r : runs) sq += (r.rgb[i] - mean) * (r.rgb[i] - mean);
        sum += sq / double(K - 1) / (mean * mean + kRelMseEpsilon);
    }
    return sum / double(n);
}

}  // namespace

std::string AutoMethodChoice::log() const {
    char head[96];
    std::snprintf(head, sizeof head, "method auto: %s (pilot %.1f s: relMSE x seconds at full size",
                  best().name.c_str(), pilotSeconds);
    std::string out = head;
    for (const AutoCandidate& c : candidates) {
        char item[128];
        std::snprintf(item, sizeof item, "%s %s %.3g (%.3f s a %s)", &c == &candidates.front() ? "" : ",",
                      c.name.c_str(), c.errorSeconds, c.unitSeconds,
                      c.request.method == "path" ? "sample per pixel" : "pass");
        out += item;
    }
    return out + "; fg's bias is not counted)\n";
}

double AutoMethodChoice::fgBudgetSeconds(int width, int height) const {
    return candidates.front().unitSeconds * defaultPasses(RenderMethod::FinalGather, width, height);
}

uint32_t AutoMethodChoice::unitsWithoutBudget(int width, int height) const {
    const double units = fgBudgetSeconds(width, height) / std::max(best().unitSeconds, 1e-9);
    return uint32_t(std::clamp(std::llround(units), 1LL, 1LL << 20));
}

AutoMethodChoice chooseRenderMethod(Device& device, const Scene& scene, const PreparedScene& prepared,
                                    const RenderRequest& request) {
    const Clock::time_point start = Clock::now();
    const int width = scene.camera.width, height = scene.camera.height;
    // A quarter of the size, but at least kPilotMinWidth wide (the whole image if narrower): the
    // variance of a few hundred pixels swings with single fireflies.
    Scene pilot = scene;
    pilot.camera.width = std::min(width, std::max(kPilotMinWidth, width / kPilotShrink));
    pilot.camera.height = std::max(1, int(std::lround(double(height) * pilot.camera.width / width)));
    const double pixelRatio = double(width) * height / (double(pilot.camera.width) * double(pilot.camera.height));
    AutoMethodChoice c;

    // fg: the full render's settings, one pass per seed; with a caustic map also the 6×6 split
    // (unless the request fixes the split itself).
    RenderRequest fgRequest = request;
    fgRequest.method = "fg";
    c.candidates.push_back({"fg", fgRequest});
    const PhotonRenderSettings fgDefaults = resolveRenderSettings(fgRequest, prepared.plan, width, height).settings;
    if (fgEyeSamplesReadCaustics(fgDefaults, prepared.plan) && !request.strata && !request.gatherRays &&
        !request.lightSamples) {
        RenderRequest wide = fgRequest;
        wide.strata = 6;
        wide.gatherRays = 2;
        wide.lightSamples = 2;
        c.candidates.push_back({"fg 6x6x2", wide});
    }
    for (AutoCandidate& candidate : c.candidates) {
        RenderRequest one = candidate.request;
        one.seconds = 0.0;
        one.passes = 1;
        PhotonRenderSettings s = resolveRenderSettings(one, prepared.plan, width, height).settings;
        s.photonBatch =
            planRenderMemory(device.info(), prepared.geometry, prepared.buffers, s, prepared.plan).photonBatch;
        std::vector<Image> img;
        double fixed = 0, scaled = 0;
        for (int i = 0; i < 2; ++i) {
            s.seed = request.seed + 1000003 * (i + 1);
            const PhotonRenderResult r =
                renderPhotonMapped(device, pilot, prepared.geometry, prepared.buffers, prepared.plan, s);
            img.push_back(r.film.resolve());
            fixed += 0.5 * (r.times.photons + r.times.maps);
            scaled += 0.5 * (r.times.total - r.times.photons - r.times.maps);
        }
        candidate.unitSeconds = fixed + scaled * pixelRatio;
        candidate.errorSeconds = renderVariance(img) * candidate.unitSeconds;
    }

    // The path tracer: kPilotSamples per pixel per seed.
    AutoCandidate path{"path", request};
    path.request.method = "path";
    std::vector<Image> img;
    double pathSeconds = 0;
    for (int i = 0; i < kPathPilotRenders; ++i) {
        PathRenderSettings p;
        p.seed = request.seed + 1000003 * (i + 1);
        p.samples = kPilotSamples;
        const PathRenderResult r = renderPathTraced(pilot, prepared.geometry, p);
        img.push_back(r.film.resolve());
        pathSeconds += r.seconds / kPathPilotRenders;
    }
    path.unitSeconds = pathSeconds / kPilotSamples * pixelRatio;
    path.errorSeconds = renderVariance(img) * pathSeconds * pixelRatio;
    c.candidates.push_back(path);

    for (size_t i = 1; i < c.candidates.size(); ++i)
        if (c.candidates[i].errorSeconds < c.candidates[c.chosen].errorSeconds) c.chosen = i;
    c.pilotSeconds = since(start);
    return c;
}

}  // namespace pcl
