#include "render/auto_method.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/clock.h"
#include "core/math.h"
#include "image/metrics.h"
#include "prep/photon_allocation.h"
#include "render/path_render.h"
#include "render/photon_renderer.h"

namespace pcl {
namespace {

constexpr int kPilotShrink = 4;         // the pilot renders width/4 × height/4 …
constexpr int kPilotMinWidth = 64;      // … and at least this wide (the whole image if narrower)
constexpr uint32_t kPilotSamples = 16;  // path tracer samples per pixel per pilot render
constexpr double kMinGatherGain = 0.9;  // change fg's gather rays only for a predicted 10 % lower error × time
constexpr float kCausticShare = 0.05f;  // pixels whose caustic light exceeds this share are left out of fg's bias
// … and pixels whose emitted light (lamps seen directly or in mirrors, the sky) exceeds it: fg
// finds that light by the same eye paths as the path tracer, so it holds none of fg's bias, but
// a lamp's edge there is the noisiest light of both pilots (motion-dof: one 8×8 block holding the
// lamp's reflection in the chrome ball read 2.0e-3 of the pilot's 2.2e-3 mean squared bias,
// where fg's bias against the 64-px reference is 1e-4).
constexpr float kEmittedShare = 0.05f;
// fg's bias is not measured where caustic fireflies make up more than this share of the path
// tracer's pilot variance: its mean then lacks the (indirect) caustic light its few samples have
// not found, about the caustic share of the light, which would read as fg's bias (cornell-spheres,
// 49 % fireflies: 2.6e-3, where fg's whole relMSE at 60 s is 8.3e-4). Such a path tracer does not
// win anyway (cornell-spheres, cornell-glossy, the courtyard: 70-99 %).
constexpr double kBiasFireflyShare = 0.4;
constexpr int kPathPilotRenders = 6;  // the path tracer's pilot renders: its fireflies need more than
                                      // two for a steady variance (fg's passes are dearer: two)

// dst += 0.5 src (dst empty: 0.5 src).
void accumulateHalf(Image& dst, const Image& src) {
    if (dst.rgb.empty()) dst = Image(src.width, src.height);
    for (size_t i = 0; i < src.rgb.size(); ++i) dst.rgb[i] += 0.5f * src.rgb[i];
}

// The relative variance of one render from K ≥ 2 independent ones: per pixel and channel the
// sample variance over the K over (mean² + ε) (relMSE's ε), averaged: the whole image as its
// own part.
double renderVariance(const std::vector<Image>& runs) { return partVariance(runs, runs); }

// ∫ L² dω / ∫ L dω over the sky, per channel: the radiance a sample that finds the sky at random
// (in proportion to solid angle) is worth, weighted by how much light it brings.
Vec3 skyRadianceByItsLight(const Environment& env) {
    if (env.image.rgb.empty()) return env.scale;
    const int W = env.image.width, H = env.image.height;
    double l1[3] = {0, 0, 0}, l2[3] = {0, 0, 0};
    for (int y = 0; y < H; ++y) {
        const double omega = 2.0 * kPiD / W * (std::cos(kPiD * y / double(H)) - std::cos(kPiD * (y + 1) / double(H)));
        for (int x = 0; x < W; ++x) {
            const Vec3 t = env.image.at(x, y);
            const double L[3] = {double(t.x) * env.scale.x, double(t.y) * env.scale.y, double(t.z) * env.scale.z};
            for (int c = 0; c < 3; ++c) {
                l1[c] += L[c] * omega;
                l2[c] += L[c] * L[c] * omega;
            }
        }
    }
    auto ratio = [](double a, double b) { return b > 0 ? float(a / b) : 0.0f; };
    return {ratio(l2[0], l1[0]), ratio(l2[1], l1[1]), ratio(l2[2], l1[2])};
}

}  // namespace

Vec3 causticEmitterRadiance(const Scene& scene, const SceneBuffers& buffers) {
    double weightSum = 0.0, radiance[3] = {0, 0, 0};
    for (const PclLight& light : buffers.lights) {
        const double w = scalarPower(light) * double(emitFraction(light));
        if (!(w > 0)) continue;
        weightSum += w;
        Vec3 L(0.0f);
        if (light.type == PCL_LIGHT_TRIANGLE && light.area > 0) {
            const float k = 1.0f / (kPi * light.area);
            L = {light.power[0] * k, light.power[1] * k, light.power[2] * k};
        } else if (light.type == PCL_LIGHT_ENVIRONMENT) {
            L = skyRadianceByItsLight(scene.environment);
        }
        radiance[0] += w * L.x;
        radiance[1] += w * L.y;
        radiance[2] += w * L.z;
    }
    if (!(weightSum > 0)) return Vec3(0.0f);
    return {float(radiance[0] / weightSum), float(radiance[1] / weightSum), float(radiance[2] / weightSum)};
}

double causticFireflyVariance(const Image& caustic, const Image& albedo, const Image& mean, Vec3 emitterRadiance) {
    const float Le[3] = {emitterRadiance.x, emitterRadiance.y, emitterRadiance.z};
    const size_t n = mean.rgb.size();
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        const double m = mean.rgb[i];
        sum += std::max(0.0f, caustic.rgb[i]) * std::max(0.0f, albedo.rgb[i]) * Le[i % 3] / (m * m + kRelMseEpsilon);
    }
    return n ? sum / double(n) : 0.0;
}

double partVariance(const std::vector<Image>& parts, const std::vector<Image>& totals) {
    const size_t K = parts.size(), n = parts.front().rgb.size();
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double mean = 0.0, total = 0.0, sq = 0.0;
        for (size_t k = 0; k < K; ++k) mean += parts[k].rgb[i], total += totals[k].rgb[i];
        mean /= double(K);
        total /= double(K);
        for (const Image& r : parts) sq += (r.rgb[i] - mean) * (r.rgb[i] - mean);
        sum += sq / double(K - 1) / (total * total + kRelMseEpsilon);
    }
    return sum / double(n);
}

double squaredBias(const std::vector<Image>& a, const std::vector<Image>& b, const std::vector<bool>& keep) {
    const size_t Ka = a.size(), Kb = b.size(), n = a.front().rgb.size();
    double sum = 0.0, sumSq = 0.0;
    size_t count = 0;
    for (size_t i = 0; i < n; ++i) {
        if (!keep.empty() && !keep[i / 3]) continue;
        double ma = 0.0, mb = 0.0, va = 0.0, vb = 0.0;
        for (const Image& r : a) ma += r.rgb[i];
        for (const Image& r : b) mb += r.rgb[i];
        ma /= double(Ka);
        mb /= double(Kb);
        for (const Image& r : a) va += (r.rgb[i] - ma) * (r.rgb[i] - ma);
        for (const Image& r : b) vb += (r.rgb[i] - mb) * (r.rgb[i] - mb);
        va /= double(Ka - 1) * double(Ka);  // the variance of the mean
        vb /= double(Kb - 1) * double(Kb);
        const double m = 0.5 * (ma + mb);
        const double t = ((ma - mb) * (ma - mb) - va - vb) / (m * m + kRelMseEpsilon);
        sum += t;
        sumSq += t * t;
        ++count;
    }
    if (count < 2) return 0.0;
    const double mean = sum / double(count);
    const double standardError = std::sqrt(std::max(0.0, sumSq / double(count) - mean * mean) / double(count));
    return std::max(0.0, mean - 2.0 * standardError);
}

uint32_t gatherRaysForTheIndirectShare(uint32_t g0, double V, double Vi, double T, double Ti, uint32_t maxRays) {
    if (!(Vi > 0.0) || !(V > Vi) || !(Ti > 0.0) || !(T > Ti) || g0 == 0) return g0;
    const double ratio = std::sqrt(Vi * (T - Ti) / ((V - Vi) * Ti));
    return uint32_t(std::clamp<long long>(std::llround(double(g0) * ratio), 1, maxRays));
}

double predictedErrorSeconds(uint32_t g0, uint32_t g, double V, double Vi, double T, double Ti) {
    const double r = double(g) / double(g0);
    return (V - Vi + Vi / r) * (T - Ti + Ti * r);
}

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
        if (c.request.method != "path") {
            std::snprintf(item, sizeof item, " + bias %.3g", c.biasSquared);
            out += item;
        }
        if (!c.tuned.empty()) out += " (" + c.tuned + ")";
        if (c.fireflyShare > 0) {
            std::snprintf(item, sizeof item, " (%.0f %% of it caustic fireflies)", 100.0 * c.fireflyShare);
            out += item;
        }
    }
    char tail[160];
    std::snprintf(tail, sizeof tail,
                  "; the lowest relMSE at %.1f s wins: relMSE x seconds / %.1f + fg's squared bias against the path "
                  "tracer)\n",
                  budgetSeconds, budgetSeconds);
    return out + tail;
}

double AutoMethodChoice::predictedRelMse(const AutoCandidate& c) const {
    return c.errorSeconds / std::max(budgetSeconds, 1e-3) + c.biasSquared;
}

double AutoMethodChoice::fgBudgetSeconds(int width, int height) const {
    return fgDefaultPassSeconds * defaultPasses(RenderMethod::FinalGather, width, height);
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
    c.candidates.push_back({"fg", fgRequest, 0, 0, 0, 0, {}});
    const PhotonRenderSettings fgDefaults = resolveRenderSettings(fgRequest, prepared.plan, width, height).settings;
    if (fgEyeSamplesReadCaustics(fgDefaults, prepared.plan) && !request.strata && !request.gatherRays &&
        !request.lightSamples) {
        RenderRequest wide = fgRequest;
        wide.strata = 6;
        wide.gatherRays = 2;
        wide.lightSamples = 2;
        c.candidates.push_back({"fg 6x6x2", wide, 0, 0, 0, 0, {}});
    }
    // fg's first candidate also measures the caustic light and the albedo that the path tracer's
    // caustic fireflies are made of (causticFireflyVariance), when non-delta emitters send caustic photons.
    const Vec3 fireflyRadiance = causticEmitterRadiance(scene, prepared.buffers);
    const bool measureFireflies = fireflyRadiance.x > 0 || fireflyRadiance.y > 0 || fireflyRadiance.z > 0;
    Image fgMean, fgCaustic, fgEmitted, fgAlbedo;
    std::vector<std::vector<Image>> fgImages;  // per fg candidate, its two renders (for its bias)
    for (AutoCandidate& candidate : c.candidates) {
        const bool first = &candidate == &c.candidates.front();
        RenderRequest one = candidate.request;
        one.seconds = 0.0;
        one.passes = 1;
        PhotonRenderSettings s = resolveRenderSettings(one, prepared.plan, width, height).settings;
        s.photonBatch =
            planRenderMemory(device.info(), prepared.geometry, prepared.buffers, s, prepared.plan).photonBatch;
        s.aovs = true;  // the indirect part's variance; the first's caustic light and albedo
        std::vector<Image> img, indirect;
        double fixed = 0, scaled = 0, indirectSeconds = 0;
        for (int i = 0; i < 2; ++i) {
            s.seed = request.seed + 1000003 * (i + 1);
            const PhotonRenderResult r =
                renderPhotonMapped(device, pilot, prepared.geometry, prepared.buffers, prepared.plan, s);
            img.push_back(r.film.resolve());
            indirect.push_back(r.aovs.indirect.resolve());
            if (first) {  // the bias's caustic mask; the albedo only for the fireflies
                accumulateHalf(fgMean, img.back());
                accumulateHalf(fgCaustic, r.aovs.caustic.resolve());
                accumulateHalf(fgEmitted, r.aovs.emitted.resolve());
                if (measureFireflies) accumulateHalf(fgAlbedo, r.aovs.albedo.resolve());
            }
            fixed += 0.5 * (r.times.photons + r.times.maps);
            scaled += 0.5 * (r.times.total - r.times.photons - r.times.maps);
            indirectSeconds += 0.5 * r.times.indirect * pixelRatio;
        }
        candidate.unitSeconds = fixed + scaled * pixelRatio;
        fgImages.push_back(img);
        const double variance = renderVariance(img);
        candidate.errorSeconds = variance * candidate.unitSeconds;
        if (first) c.fgDefaultPassSeconds = candidate.unitSeconds;
        // Gather rays where the indirect part's noise needs them (unless the request fixes them).
        if (request.gatherRays) continue;
        const double Vi = partVariance(indirect, img);
        // At most twice the default: the indirect part's variance also holds the photon map's own
        // noise (a fresh map each pass), which more gather rays in a pass do not average, so the
        // formula overstates their worth (cornell-spheres-point at 256²: it asked for 11 rays,
        // where 4 measured 16 % lower MSE than 2 at 30 s and 11 took 3x the time a pass).
        const uint32_t g = gatherRaysForTheIndirectShare(s.gatherRays, variance, Vi, candidate.unitSeconds,
                                                         indirectSeconds, std::min(16u, 2 * s.gatherRays));
        // Only a gain the pilot can resolve: its timings vary by more than a few per cent, and
        // on motion-dof a 1 % predicted gain (2 -> 3 rays) tipped its close fg/path call by noise.
        const double predicted =
            predictedErrorSeconds(s.gatherRays, g, variance, Vi, candidate.unitSeconds, indirectSeconds);
        if (g == s.gatherRays || predicted > kMinGatherGain * candidate.errorSeconds) continue;
        char why[160];
        std::snprintf(why, sizeof why,
                      "gather rays %u -> %u: the indirect part holds %.0f %% of its variance and %.0f %% of its time",
                      s.gatherRays, g, 100.0 * Vi / variance, 100.0 * indirectSeconds / candidate.unitSeconds);
        candidate.tuned = why;
        candidate.request.gatherRays = g;
        candidate.errorSeconds = predicted;
        candidate.unitSeconds += indirectSeconds * (double(g) / s.gatherRays - 1.0);
    }

    // The path tracer: kPilotSamples per pixel per seed.
    AutoCandidate path{"path", request, 0, 0, 0, 0, {}};
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
    const double measured = renderVariance(img);
    const double fireflies =
        measureFireflies ? causticFireflyVariance(fgCaustic, fgAlbedo, fgMean, fireflyRadiance) / kPilotSamples : 0.0;
    path.fireflyShare = fireflies > 0 ? fireflies / (measured + fireflies) : 0.0;
    path.errorSeconds = (measured + fireflies) * pathSeconds * pixelRatio;

    // fg's bias against the path tracer's pilot, where fg's caustic light is under a twentieth
    // of the pixel (there the path tracer's few samples rarely find the caustic and its mean
    // and variance are unsteady: they would read as fg's bias) and so is its emitted light.
    if (path.fireflyShare <= kBiasFireflyShare) {
        std::vector<bool> keep(size_t(fgMean.width) * fgMean.height, true);
        for (size_t p = 0; p < keep.size(); ++p) {
            const float* m = &fgMean.rgb[3 * p];
            const float* k = &fgCaustic.rgb[3 * p];
            const float* e = &fgEmitted.rgb[3 * p];
            keep[p] = !(k[0] + k[1] + k[2] > kCausticShare * (m[0] + m[1] + m[2])) &&
                      !(e[0] + e[1] + e[2] > kEmittedShare * (m[0] + m[1] + m[2]));
        }
        for (size_t i = 0; i < fgImages.size(); ++i) c.candidates[i].biasSquared = squaredBias(fgImages[i], img, keep);
    }
    c.candidates.push_back(path);

    // The lowest relMSE predicted at the budget (without one, at fg's default time).
    c.budgetSeconds = request.seconds > 0 ? request.seconds : c.fgBudgetSeconds(width, height);
    for (size_t i = 1; i < c.candidates.size(); ++i)
        if (c.predictedRelMse(c.candidates[i]) < c.predictedRelMse(c.candidates[c.chosen])) c.chosen = i;
    c.pilotSeconds = since(start);
    return c;
}

}  // namespace pcl
