#include "render/sweep.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <thread>

#include "core/clock.h"
#include "core/error.h"
#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "image/film.h"
#include "image/image_io.h"
#include "image/metrics.h"
#include "prep/environment_map.h"
#include "prep/media_support.h"
#include "prep/prepared_scene.h"
#include "reference/path_tracer.h"
#include "render/auto_method.h"
#include "render/path_render.h"
#include "scene/load_scene.h"

namespace pcl {
namespace {

uint64_t splitmix64(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}
// The seed of the passes [n, 2n) of seed `seed`'s curve: independent of every other increment.
uint64_t incrementSeed(uint64_t seed, uint32_t increment) { return splitmix64(splitmix64(seed) + increment); }

// A curve: one method with one setting variant (applied over the method's defaults).
struct Curve {
    std::string name;
    RenderMethod method;
    std::string variant;  // what differs from the method's defaults ("" for none)
    std::function<void(PhotonRenderSettings&)> tweak;
    // `render --method auto --time T`: every point a fresh render of T seconds, its pilot paid from
    // T (as a user's is), the method the pilot picks; `method` is then only its first candidate.
    bool autoMethod = false;
};

// The auto curve's budgets: maxSeconds/8, /4, /2 and maxSeconds, none below kAutoMinSeconds (the
// pilot alone takes 1.5-3 s at 256²).
constexpr double kAutoMinSeconds = 5.0;
std::vector<double> autoBudgets(double maxSeconds) {
    std::vector<double> b;
    for (double t = maxSeconds / 8; t < maxSeconds * 0.99; t *= 2)
        if (t >= kAutoMinSeconds) b.push_back(t);
    b.push_back(std::max(maxSeconds, kAutoMinSeconds));
    return b;
}

std::vector<Curve> allCurves() {
    auto none = [](PhotonRenderSettings&) {};
    return {
        {"path", RenderMethod::PathTracing, "", none},
        {"direct", RenderMethod::DirectVisualisation, "", none},
        {"fg-estimate", RenderMethod::FinalGather, "gather source: full estimate",
         [](PhotonRenderSettings& s) { s.gatherSource = GatherSource::Estimate; }},
        {"fg-precomputed", RenderMethod::FinalGather, "", none},
        {"progressive", RenderMethod::Progressive, "", none},
        {"auto", RenderMethod::FinalGather, "render --method auto --time T", none, /*autoMethod=*/true},
        // Variants (full form): one setting changed at a time.
        {"fg-precomputed-rays/4", RenderMethod::FinalGather, "gather rays / 4",
         [](PhotonRenderSettings& s) { s.gatherRays = std::max(1u, s.gatherRays / 4); }},
        {"fg-precomputed-photons/4", RenderMethod::FinalGather, "global photons / 4",
         [](PhotonRenderSettings& s) { s.globalPhotons = std::max(1000u, s.globalPhotons / 4); }},
        {"direct-k200", RenderMethod::DirectVisualisation, "k 200", [](PhotonRenderSettings& s) { s.globalK = 200; }},
        {"direct-box", RenderMethod::DirectVisualisation, "box filter",
         [](PhotonRenderSettings& s) { s.filter = EstimateFilter::Box; }},
        {"fg-estimate-hashgrid", RenderMethod::FinalGather, "gather source: full estimate; hash grid",
         [](PhotonRenderSettings& s) {
             s.gatherSource = GatherSource::Estimate;
             s.structure = KnnStructure::HashGrid;
         }},
        {"direct-hashgrid", RenderMethod::DirectVisualisation, "hash grid",
         [](PhotonRenderSettings& s) { s.structure = KnnStructure::HashGrid; }},
        {"progressive-photons*4", RenderMethod::Progressive, "global photons x 4",
         [](PhotonRenderSettings& s) { s.globalPhotons *= 4; }},
    };
}

// render's defaults for the method (resolveRenderSettings with nothing given); quick: fewer
// photons and rays.
PhotonRenderSettings methodDefaults(RenderMethod method, const RenderPlan& plan, int width, int height, bool quick) {
    RenderRequest q;
    q.method = renderMethodName(method);
    PhotonRenderSettings s = resolveRenderSettings(q, plan, width, height).settings;
    if (quick) {
        s.globalPhotons = std::max(2000u, s.globalPhotons / 8);
        s.causticPhotons = std::max(2000u, s.causticPhotons / 8);
        s.gatherRays = std::max(1u, s.gatherRays / 4);
        s.lightSamples = 4;
    }
    return s;
}

double mse(const ImageErrors& e) { return e.rmse * e.rmse; }

// Per budget of a curve: the sums over seeds of each value and its square (bias² and variance).
struct SeedMoments {
    std::vector<double> sum, sumSq;
    double mseSum = 0, secondsSum = 0;
    uint32_t count = 0;
    void add(const Image& img, double m, double seconds) {
        if (sum.empty()) sum.assign(img.rgb.size(), 0.0), sumSq.assign(img.rgb.size(), 0.0);
        for (size_t i = 0; i < img.rgb.size(); ++i) sum[i] += img.rgb[i], sumSq[i] += double(img.rgb[i]) * img.rgb[i];
        mseSum += m;
        secondsSum += seconds;
        ++count;
    }
};

std::string fmt(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}

// One point of the auto curve: what `render --method auto --time T` renders (the pilot, then the
// method it picks for the rest of T), timed as a whole.
struct AutoPoint {
    SweepRow row;  // method "auto: <choice>", passes / samples per pixel, times, settings
    Image image;
};
AutoPoint autoPoint(Device& device, const Scene& scene, const PreparedScene& prepared, double T, uint64_t seed,
                    int threads) {
    const Clock::time_point start = Clock::now();
    RenderRequest q;
    q.method = "auto";
    q.seed = seed;
    q.seconds = T;
    const AutoMethodChoice choice = chooseRenderMethod(device, scene, prepared, q);
    RenderRequest chosen = choice.best().request;
    chosen.seconds = std::max(0.1, T - choice.pilotSeconds);
    chosen.seed = seed;
    AutoPoint p;
    SweepRow& row = p.row;
    row.method = "auto: " + choice.best().name;
    row.seed = std::to_string(seed);
    std::string log = choice.log();
    if (!log.empty() && log.back() == '\n') log.pop_back();
    if (chosen.method == "path") {
        PathRenderSettings ps;
        ps.seed = seed;
        ps.threads = threads;
        ps.samples = 0;
        ps.seconds = chosen.seconds;
        const PathRenderResult r = renderPathTraced(scene, prepared.geometry, ps);
        p.image = r.film.resolve();
        row.passes = row.samplesPerPixel = r.samples;
    } else {
        const int w = scene.camera.width, h = scene.camera.height;
        PhotonRenderSettings s = resolveRenderSettings(chosen, prepared.plan, w, h).settings;
        s.photonBatch =
            planRenderMemory(device.info(), prepared.geometry, prepared.buffers, s, prepared.plan).photonBatch;
        const PhotonRenderResult r =
            renderPhotonMapped(device, scene, prepared.geometry, prepared.buffers, prepared.plan, s);
        p.image = r.film.resolve();
        row.times = r.times;
        row.passes = r.passes;
        row.samplesPerPixel = uint64_t(r.passes) * s.strata * s.strata;
        log += "; " + r.summary;
    }
    row.times.total = since(start);  // the pilot included
    char budget[48];
    std::snprintf(budget, sizeof budget, "render --method auto --time %g; ", T);
    row.settings = budget + log;
    return p;
}

}  // namespace

std::vector<std::string> sweepCurveNames(bool quick) {
    std::vector<std::string> names;
    for (const Curve& c : allCurves()) {
        if (quick && !c.variant.empty() && c.name != "fg-estimate")
            continue;  // auto too: its pilot alone
                       // outlasts a quick curve
        names.push_back(c.name);
    }
    return names;
}

std::string sweepCsvHeader() {
    return "scene,curve,method,variant_settings,device,seed,passes,samples_per_pixel,seconds,seconds_photons,"
           "seconds_maps,seconds_camera,seconds_eye_paths,seconds_direct,seconds_caustic,seconds_indirect,"
           "seconds_volume,seconds_accumulate,rmse,relmse,mean_ratio,max_error,mse,bias2,variance\n";
}

std::string sweepCsvLine(const SweepRow& r) {
    auto quote = [](const std::string& s) {
        std::string q = "\"";
        for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
        return q + "\"";
    };
    std::ostringstream o;
    const StageTimes& t = r.times;
    o << r.scene << "," << r.curve << "," << r.method << "," << quote(r.settings) << "," << quote(r.device) << ","
      << r.seed << "," << r.passes << "," << r.samplesPerPixel << "," << fmt(t.total) << "," << fmt(t.photons) << ","
      << fmt(t.maps) << "," << fmt(t.camera) << "," << fmt(t.eyePaths) << "," << fmt(t.direct) << "," << fmt(t.caustic)
      << "," << fmt(t.indirect) << "," << fmt(t.volume) << "," << fmt(t.accumulate) << "," << fmt(r.rmse) << ","
      << fmt(r.relMse) << "," << fmt(r.meanRatio) << "," << fmt(r.maxError) << "," << fmt(r.mse) << ","
      << (r.split ? fmt(r.bias2) : "") << "," << (r.split ? fmt(r.variance) : "") << "\n";
    return o.str();
}

std::vector<SweepRow> runSweep(const SweepOptions& o, const std::function<void(const std::vector<SweepRow>&)>& onRow) {
    namespace fs = std::filesystem;
    if (!fs::is_regular_file(o.scenePath)) throw InputError("sweep: scene " + o.scenePath + ": no such file");
    if (!fs::is_regular_file(o.referencePath))
        throw InputError("sweep: reference " + o.referencePath + ": no such file");
    if (o.seeds < 1) throw InputError("sweep: --seeds must be at least 1");
    if (!(o.maxSeconds > 0)) throw InputError("sweep: the time budget must be positive");

    // Which curves: all of the form, or the named ones (in the sweep's order).
    std::vector<Curve> curves;
    {
        const std::vector<std::string> form = sweepCurveNames(o.quick);
        for (const std::string& n : o.curves) {
            bool known = false;
            for (const Curve& c : allCurves()) known |= c.name == n;
            if (!known) {
                std::string list;
                for (const Curve& c : allCurves()) list += (list.empty() ? "" : ", ") + c.name;
                throw InputError("sweep: unknown curve '" + n + "'; expected one of " + list);
            }
        }
        for (const Curve& c : allCurves()) {
            bool wanted = o.curves.empty() ? std::find(form.begin(), form.end(), c.name) != form.end()
                                           : std::find(o.curves.begin(), o.curves.end(), c.name) != o.curves.end();
            if (wanted) curves.push_back(c);
        }
    }

    Image reference = readImage(o.referencePath);
    Scene scene = loadScene(o.scenePath);
    // Refused before any curve runs, not after the path tracer's. Media: fg's gather rays do not
    // carry them yet, so a sweep of a scene with media leaves its fg curves out (refused when asked
    // for by name); the path tracer, direct and progressive render media.
    refuseEnvironmentInMediaWithoutPathTracer(scene, "sweep (its photon-method curves)");
    if (scene.hasMedia()) {
        for (const Curve& c : curves)
            if (c.method == RenderMethod::FinalGather && !o.curves.empty())
                refuseMediaWithoutPathTracer(scene,
                                             "sweep curve " + c.name + " (fg's gather rays do not carry media yet)");
        const size_t before = curves.size();
        curves.erase(std::remove_if(curves.begin(), curves.end(),
                                    [](const Curve& c) { return c.method == RenderMethod::FinalGather; }),
                     curves.end());
        if (curves.size() != before)
            std::fprintf(stderr,
                         "sweep: %zu fg curve(s) left out (auto's included): the scene has participating media, "
                         "which fg's gather rays (and so auto's pilot) do not carry yet\n",
                         before - curves.size());
    }
    Camera& cam = scene.camera;
    // The reference's size sets the render's; a different aspect ratio is a different image.
    const double camAspect = double(cam.width) / cam.height, refAspect = double(reference.width) / reference.height;
    if (std::abs(camAspect / refAspect - 1.0) > 0.01)
        throw InputError("sweep: reference " + o.referencePath + " is " + std::to_string(reference.width) + "x" +
                         std::to_string(reference.height) + " (aspect " + fmt(refAspect) + ") but the camera of " +
                         o.scenePath + " is " + std::to_string(cam.width) + "x" + std::to_string(cam.height) +
                         " (aspect " + fmt(camAspect) + "): expected a reference at the camera's aspect ratio");
    if (o.quick) {
        // A quarter (or half) of the reference's width: the box average of its pixels is the
        // reference of the bigger pixels (the film's filter is the pixel's box).
        int factor = reference.width >= 32 && reference.width % 4 == 0 && reference.height % 4 == 0 ? 4
                     : reference.width % 2 == 0 && reference.height % 2 == 0                        ? 2
                                                                                                    : 1;
        reference = boxDownsample(reference, factor);
    }
    cam.width = reference.width;
    cam.height = reference.height;
    // As render prepares them: fg and auto leave a spread sky's caustics to the gather rays,
    // direct and progressive keep its photons (planSettingsFor).
    // The two differ only where the sky sends caustic photons and its light is spread: only then is
    // the scene prepared twice.
    const PreparedScene forOthers = prepareScene(scene, planSettingsFor("progressive"));
    std::optional<PreparedScene> fgOwn;
    if (forOthers.plan.skyCausticPhotons && forOthers.paths.skySpread)
        fgOwn.emplace(prepareScene(scene, planSettingsFor("fg")));
    const PreparedScene& forFg = fgOwn ? *fgOwn : forOthers;
    const std::string sceneName = fs::path(o.scenePath).stem().string();

    std::unique_ptr<Device> device;
    std::vector<SweepRow> rows;
    auto say = [&](const std::string& line) {
        if (o.progress) o.progress(line);
    };
    const uint32_t maxBudget = 1u << 20;
    // A point's errors against the reference: the row is kept (and reported), the image's moments
    // added for the bias²/variance split.
    auto record = [&](SweepRow& row, const Image& image, std::vector<SeedMoments>& moments, size_t bi,
                      const std::string& amount) {
        ImageErrors e = compare(image, reference);
        row.rmse = e.rmse, row.relMse = e.relMse, row.meanRatio = e.meanRatio, row.maxError = e.maxAbsDiff;
        row.mse = mse(e);
        rows.push_back(row);
        if (o.seeds > 1) moments[bi].add(image, row.mse, row.times.total);
        say(sceneName + " " + row.curve + " seed " + row.seed + ": " + amount + ", " + fmt(row.times.total) +
            " s, relMSE " + fmt(row.relMse) + ", RMSE " + fmt(row.rmse) + ", mean ratio " + fmt(row.meanRatio));
        if (onRow) onRow(rows);
    };

    for (const Curve& curve : curves) {
        const bool path = curve.method == RenderMethod::PathTracing;
        const PreparedScene& prepared = curve.method == RenderMethod::FinalGather || curve.autoMethod ? forFg
                                                                                                      : forOthers;
        const SceneGeometry& geometry = prepared.geometry;
        const SceneBuffers& buffers = prepared.buffers;
        const RenderPlan& plan = prepared.plan;
        PhotonRenderSettings base = methodDefaults(curve.method, plan, cam.width, cam.height, o.quick);
        if (!path) {
            curve.tweak(base);
            if (!device) device = std::make_unique<Device>(Device::open(o.device));
            base.photonBatch = planRenderMemory(device->info(), geometry, buffers, base, plan).photonBatch;
            // One untimed pass: builds this configuration's kernels.
            PhotonRenderSettings warm = base;
            warm.passes = 1;
            warm.seed = ~0ull;
            renderPhotonMapped(*device, scene, geometry, buffers, plan, warm);
        }
        const std::string deviceName =
            path ? "ref (CPU path tracer, " +
                       std::to_string(o.threads ? o.threads : int(std::thread::hardware_concurrency())) + " threads)"
                 : device->info().name;

        std::vector<uint32_t> budgets;  // set by the first seed, repeated by the others
        std::vector<SeedMoments> moments;
        std::string settingsText;
        for (uint32_t si = 0; si < o.seeds; ++si) {
            // Seeds 1 and 2 made the references (scripts/make_references.py): the path tracer's
            // sample i of a seed is the same in every render, so a repeat with either would share
            // the reference's samples and read too good. Repeats step by 1000.
            const uint64_t seed = o.seed + 1000 * uint64_t(si);
            Film film(cam.width, cam.height);
            StageTimes cumulative;
            uint32_t done = 0;  // passes (or samples per pixel) in `film`
            for (size_t bi = 0;; ++bi) {
                if (curve.autoMethod) {
                    const std::vector<double> seconds = autoBudgets(o.maxSeconds);
                    if (bi >= seconds.size()) break;
                    if (si == 0) budgets.push_back(uint32_t(bi)), moments.emplace_back();
                    AutoPoint point = autoPoint(*device, scene, prepared, seconds[bi], seed, o.threads);
                    SweepRow& row = point.row;
                    row.scene = sceneName, row.curve = curve.name, row.device = deviceName;
                    record(row, point.image, moments, bi, fmt(seconds[bi]) + " s budget");
                    continue;
                }
                uint32_t target;
                if (si == 0) {
                    if (bi == 0) {
                        target = 1;
                    } else {
                        // Double, but aim the last point at maxSeconds rather than twice it.
                        const double perPass = cumulative.total / std::max<uint32_t>(done, 1);
                        const double last = rows.empty() ? 0 : rows.back().times.total;
                        if (last >= o.maxSeconds || done >= maxBudget) break;
                        // Progressive renders every point from scratch: a last point only a few
                        // passes beyond one near the budget would cost a whole render for nothing.
                        // The others: a point within 10 % of the budget ends the curve (the
                        // next would add a pass or two at the cost of a timing's noise).
                        if (last >= (curve.method == RenderMethod::Progressive ? 0.75 : 0.9) * o.maxSeconds) break;
                        target = done * 2;
                        const double perUnit = curve.method == RenderMethod::Progressive ? last / done : perPass;
                        if (perUnit > 0 && target * perUnit > o.maxSeconds * 1.05)
                            target = std::max(done + 1, uint32_t(std::ceil(o.maxSeconds / perUnit)));
                    }
                    budgets.push_back(target);
                    moments.emplace_back();
                } else {
                    if (bi >= budgets.size()) break;
                    target = budgets[bi];
                }

                SweepRow row;
                row.scene = sceneName;
                row.curve = curve.name;
                row.method = renderMethodName(curve.method);
                row.device = deviceName;
                row.seed = std::to_string(seed);
                if (path) {
                    PathRenderSettings ps;
                    ps.seed = seed;
                    ps.threads = o.threads;
                    ps.firstSample = done;
                    ps.samples = target - done;
                    auto t = Clock::now();
                    film.merge(renderPathTraced(scene, geometry, ps).film);
                    cumulative.total += since(t);
                    const PathTracerSettings defaults;
                    settingsText = "unidirectional, NEE + MIS, Russian roulette from bounce " +
                                   std::to_string(defaults.rouletteDepth) + ", max depth " +
                                   std::to_string(defaults.maxDepth);
                    row.samplesPerPixel = target;
                } else {
                    PhotonRenderSettings s = base;
                    PhotonRenderResult r;
                    if (curve.method == RenderMethod::Progressive) {
                        // From scratch: the radius schedule follows the pass index.
                        s.passes = target;
                        s.seed = seed;
                        r = renderPhotonMapped(*device, scene, geometry, buffers, plan, s);
                        film = r.film;
                        cumulative = r.times;
                    } else {
                        s.passes = target - done;
                        s.seed = incrementSeed(seed, uint32_t(bi));
                        r = renderPhotonMapped(*device, scene, geometry, buffers, plan, s);
                        film.merge(r.film);
                        cumulative += r.times;
                    }
                    if (r.nonFiniteSamples)
                        say("warning: " + std::to_string(r.nonFiniteSamples) + " non-finite samples dropped");
                    settingsText = r.summary;
                    row.samplesPerPixel = uint64_t(target) * s.strata * s.strata;
                }
                done = target;
                row.passes = target;
                row.times = cumulative;
                row.settings = (curve.variant.empty() ? std::string() : curve.variant + "; ") + settingsText;
                record(row, film.resolve(), moments, bi, std::to_string(target) + (path ? " spp" : " passes"));
            }
        }
        if (o.seeds > 1) {
            for (size_t bi = 0; bi < budgets.size(); ++bi) {
                const SeedMoments& m = moments[bi];
                const double S = m.count;
                Image mean(reference.width, reference.height);
                double var = 0;
                for (size_t i = 0; i < m.sum.size(); ++i) {
                    double mu = m.sum[i] / S;
                    mean.rgb[i] = float(mu);
                    var += std::max(0.0, (m.sumSq[i] - S * mu * mu) / (S - 1));
                }
                var /= double(m.sum.size());
                ImageErrors e = compare(mean, reference);
                SweepRow row;
                row.scene = sceneName;
                row.curve = curve.name;
                row.method = curve.autoMethod ? "auto" : renderMethodName(curve.method);
                row.device = deviceName;
                row.seed = "all";
                // The auto curve's budgets are seconds (its points' own rows say what they rendered).
                row.passes = curve.autoMethod ? 0 : budgets[bi];
                row.samplesPerPixel = curve.autoMethod ? 0
                                      : path           ? budgets[bi]
                                                       : uint64_t(budgets[bi]) * base.strata * base.strata;
                row.times.total = m.secondsSum / S;
                row.settings = (curve.variant.empty() ? std::string() : curve.variant + "; ") + "mean image over " +
                               std::to_string(m.count) + " seeds";
                row.rmse = e.rmse, row.relMse = e.relMse, row.meanRatio = e.meanRatio, row.maxError = e.maxAbsDiff;
                row.mse = m.mseSum / S;
                row.split = true;
                row.variance = var;
                row.bias2 = mse(e) - var / S;
                rows.push_back(row);
                say(sceneName + " " + curve.name + " all seeds: " + std::to_string(budgets[bi]) + ": bias² " +
                    fmt(row.bias2) + ", variance " + fmt(row.variance));
            }
            if (onRow) onRow(rows);
        }
    }
    return rows;
}

}  // namespace pcl
