// `photoncl render`: scene file → linear EXR (with metadata, optional AOV layers) + sRGB PNG.
// Methods: fg (photon mapping with final gathering, the default), direct (the global map read at
// the first diffuse hit: a preview), progressive (probabilistic progressive photon mapping), path
// (the CPU reference path tracer). Options left out get defaults chosen for a clean image in
// about a minute on a 2-core CPU, and the log says what was chosen and why.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>


#include "cli/command.h"
#include "cli/memory_option.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "image/image_io.h"
#include "image/metrics.h"
#include "pipeline/memory_plan.h"
#include "pipeline/photon_pass.h"
#include "pipeline/plan.h"
#include "pipeline/projection_map.h"
#include "pipeline/scene_buffers.h"
#include "reference/path_tracer.h"
#include "render/photon_renderer.h"
#include "scene/load_scene.h"

namespace pcl::cli {
namespace {

struct RenderOptions {
    std::string scene, output, device = "cpu", method = "fg";
    int passes = 0;        // passes (path: samples per pixel); 0: the default for the method
    double seconds = 0.0;  // time budget instead of a pass count
    int width = 0, height = 0;
    uint64_t seed = 0;
    int threads = 0;
    bool quiet = false, noPng = false, visibility = false;
    uint64_t maxBufferMib = 0;  // --max-buffer-mib: applyBufferCap on the OpenCL device
    // Photon methods; 0 / empty: chosen (chooseDefaults).
    uint32_t histogramCells = 0;
    uint32_t strata = 0, globalPhotons = 0, causticPhotons = 0, k = 0, causticK = 0, gatherRays = 0,
             lightSamples = 0;
    float radius = 0.0f, alpha = 2.0f / 3.0f, maxRadius = 0.0f;
    std::string filter = "cone", gatherSource = "precomputed", aov, structure = "kd-tree";
};

std::string defaultOutput(const std::string& scenePath) {
    return std::filesystem::path(scenePath).stem().string() + ".exr";
}

// Ctrl-C (or SIGTERM): the render finishes the pass it is in and writes the passes done
// (core/interrupt.h); the path tracer, which cannot stop between passes, quits at once.
const std::atomic<bool>* gStop = nullptr;

// Part 7 of issue 6: what a render with no options uses, and why. Measured on the 2-core PoCL
// machine (README, "Rendering"): cornell-spheres at 256×256 renders in under a minute with these.
void chooseDefaults(const RenderOptions& o, const Scene& scene, const RenderPlan& plan, PhotonRenderSettings& s,
                    std::string& log) {
    std::ostringstream why;
    auto note = [&](const std::string& what, bool chosen, const std::string& reason) {
        why << "  " << what << (chosen ? "  (default: " + reason + ")" : "  (given)") << "\n";
    };
    applyRenderDefaults(s, plan,
                        {o.globalPhotons, o.causticPhotons, o.k, o.causticK, o.lightSamples, o.strata, o.gatherRays});
    if (s.method != RenderMethod::PathTracing)
        s.passes = o.passes ? o.passes : (o.seconds > 0 ? 0 : defaultPasses(s.method, scene.camera.width, scene.camera.height));
    const bool distributed = plan.lensSampling || plan.timeSampling || plan.glossySampling;
    s.passes = std::min<uint32_t>(s.passes, 1u << 20);
    note("passes " + (s.passes ? std::to_string(s.passes) : std::string("until --time")), !o.passes && !(o.seconds > 0),
         s.method == RenderMethod::FinalGather ? "10 passes of a 256x256 image (about 40 s on 2 CPU cores), scaled by pixel count, 1 to 64"
         : s.method == RenderMethod::Progressive ? "the radius shrinks by (i+α)/(i+1) per pass; 32 passes ≈ r0 × 0.56"
                                                 : "a quick preview");
    note("eye samples per pixel per pass " + std::to_string(s.strata * s.strata), !o.strata,
         distributed ? "2x2: the plan samples a lens, a shutter or glossy lobes, which need eye samples"
                     : "one stratified sample; passes add more");
    if (s.method == RenderMethod::FinalGather)
        note("gather rays " + std::to_string(s.gatherRays), !o.gatherRays,
             distributed ? "16 per eye sample, 4 eye samples per pass: the 64 per pixel and pass of a "
                           "scene without them; the indirect noise falls as "
                           "1/sqrt(passes × samples × gather rays)"
                         : "64: the indirect part's noise falls as 1/sqrt(passes × gather rays)");
    // A map the method does not build (photon_renderer's mapsFor) emits nothing.
    const RenderMaps built = mapsFor(s.method, plan);
    note("global photons per pass " + std::to_string(built.global ? s.globalPhotons : 0u), !o.globalPhotons,
         built.global ? (plan.globalMap ? "the plan's (photoncl analyze): the scene needs a global map"
                                        : "the preview reads all light from the global map")
                      : "no global map needed");
    note("caustic photons per pass " + std::to_string(built.caustic ? s.causticPhotons : 0u), !o.causticPhotons,
         built.caustic ? "the plan's: the scene has caustics"
                       : (plan.causticMap ? "the preview reads caustics from the global map" : "no caustic map needed"));
    note("light samples " + std::to_string(s.lightSamples), !o.lightSamples,
         "16 shadow rays per diffuse hit: with N gather rays and M light samples the power heuristic gives the gather "
         "rays a share growing with N/M, and gather rays find a small lamp rarely");
    note("k " + std::to_string(s.globalK) + " (caustic " + std::to_string(s.causticK) + ")", !o.k && !o.causticK,
         "Jensen's 50 photons per estimate");
    log = why.str();
}

int runPathTracer(const RenderOptions& o, Scene& scene, const SceneGeometry& geometry, const std::string& output,
                  std::chrono::steady_clock::time_point start) {
    PathTracerSettings settings;
    settings.seed = o.seed;
    settings.threads = o.threads;
    Film film(scene.camera.width, scene.camera.height);
    uint64_t samples = 0;
    PathTracerStats stats;
    Progress progress("render", !o.quiet);
    if (o.seconds > 0) {
        // Time budget: one sample per pixel per pass until the budget is spent.
        settings.samplesPerPixel = 1;
        for (int pass = 0;; ++pass) {
            double elapsed = progress.elapsedSeconds();
            if (pass > 0 && elapsed >= o.seconds) break;
            if (o.passes > 0 && pass >= o.passes) break;
            settings.firstSample = pass;
            PathTracerStats passStats;
            film.merge(PathTracer(scene, geometry, settings).render(&passStats));
            stats.samples += passStats.samples;
            stats.discardedSamples += passStats.discardedSamples;
            ++samples;
            progress.update(std::min(1.0, progress.elapsedSeconds() / o.seconds));
        }
    } else {
        settings.samplesPerPixel = o.passes > 0 ? o.passes : 64;
        settings.progress = [&](double f) { progress.update(f); };
        film = PathTracer(scene, geometry, settings).render(&stats);
        samples = settings.samplesPerPixel;
    }
    progress.finish();
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    ImageMetadata meta;
    meta.scene = o.scene;
    meta.method = o.method;
    meta.device = "ref";
    meta.samples = static_cast<int64_t>(samples);
    meta.seed = o.seed;
    meta.seconds = seconds;
    Image image = film.resolve();
    std::string written = writeLinearImage(output, image, meta);
    std::string png;
    if (!o.noPng) {
        png = std::filesystem::path(written).replace_extension(".png").string();
        if (!writeSrgbPng(png, image)) png.clear();
    }
    double sps = progress.elapsedSeconds() > 0 ? stats.samples / progress.elapsedSeconds() : 0.0;
    std::fprintf(stderr, "wrote %s%s%s: %dx%d, %llu samples/pixel, %.2fs, %.3g samples/s\n", written.c_str(),
                 png.empty() ? "" : " and ", png.c_str(), image.width, image.height,
                 static_cast<unsigned long long>(samples), seconds, sps);
    if (stats.discardedSamples)
        std::fprintf(stderr, "warning: %llu non-finite path samples were discarded\n",
                     static_cast<unsigned long long>(stats.discardedSamples));
    return kExitOk;
}

std::vector<std::string> parseAovs(const std::string& list) {
    std::vector<std::string> out;
    std::stringstream in(list);
    std::string item;
    while (std::getline(in, item, ',')) {
        if (item.empty()) continue;
        if (item != "direct" && item != "caustic" && item != "indirect" && item != "emitted" && item != "albedo" &&
            item != "normal")
            throw InputError("render: --aov " + item + ": expected a comma-separated list of direct, caustic, indirect, "
                             "emitted, albedo, normal");
        out.push_back(item);
    }
    return out;
}

int runPhotonRender(const RenderOptions& o, Scene& scene, const SceneGeometry& geometry, const std::string& output,
                    std::chrono::steady_clock::time_point start) {
    if (o.device == "ref")
        throw InputError("render: --method " + o.method +
                         " runs on an OpenCL device; --device ref (the CPU twins) renders only --method path");
    std::vector<std::string> aovs = parseAovs(o.aov);
    SceneBuffers buffers = buildSceneBuffers(scene, geometry);
    buildProjectionMaps(scene, geometry, buffers);
    LightPaths paths = classifyLightPaths(scene, geometry, buffers);
    RenderPlan plan = makePlan(scene, paths);

    PhotonRenderSettings s;
    s.method = parseRenderMethod(o.method);
    s.seconds = o.seconds;
    s.seed = o.seed;
    s.filter = parseEstimateFilter(o.filter);
    s.visibility = o.visibility;
    s.structure = o.structure == "hash-grid" ? KnnStructure::HashGrid : KnnStructure::KdTree;
    s.gatherSource = o.gatherSource == "estimate" ? GatherSource::Estimate : GatherSource::Precomputed;
    s.alpha = o.alpha;
    s.histogramCells = o.histogramCells;
    s.initialRadius = o.radius;
    s.maxRadius = o.maxRadius;
    s.aovs = !aovs.empty();
    s.stop = gStop;
    std::string chosen;
    chooseDefaults(o, scene, plan, s, chosen);

    Device device = Device::open(o.device);
    applyBufferCap(device, o.maxBufferMib);
    // The memory plan for one pass's photon maps, before any work (fails early with advice).
    RenderMaps maps = mapsFor(s.method, plan);
    PhotonPassOptions pass;
    pass.buildGlobal = maps.global;
    pass.buildCaustic = maps.caustic;
    pass.globalPhotons = maps.global ? s.globalPhotons : 0;
    pass.causticPhotons = maps.caustic ? s.causticPhotons : 0;
    const MemoryPlan memory = planMemory(photonPassMemoryRequest(geometry, buffers, pass), memoryLimits(device.info()));
    requireMemoryFits(memory);
    s.photonBatch = memory.photonBatch;

    if (!o.quiet) {
        std::fprintf(stderr, "%s", formatPlan(scene, paths, plan).c_str());
        std::fprintf(stderr, "render %s with %s on %s (%s):\n%s", o.scene.c_str(), o.method.c_str(),
                     device.info().name.c_str(), device.info().platform.c_str(), chosen.c_str());
    }
    Progress progress("render", !o.quiet);
    s.onPass = [&](uint32_t, double fraction) { progress.update(fraction); };
    PhotonRenderResult r = renderPhotonMapped(device, scene, geometry, buffers, plan, s);
    progress.finish();
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    ImageMetadata meta;
    meta.scene = o.scene;
    meta.method = o.method;
    meta.device = device.info().name;
    meta.samples = static_cast<int64_t>(r.passes) * s.strata * s.strata;
    meta.seed = o.seed;
    meta.seconds = seconds;
    auto add = [&](const std::string& k, const std::string& v) { meta.extra.emplace_back(k, v); };
    add("settings", r.summary);
    add("passes", std::to_string(r.passes));
    add("globalPhotonsEmitted", std::to_string(r.globalEmitted));
    add("causticPhotonsEmitted", std::to_string(r.causticEmitted));
    add("globalPhotonsStored", std::to_string(r.globalStored));
    add("causticPhotonsStored", std::to_string(r.causticStored));
    add("platform", device.info().platform);
    if (s.method == RenderMethod::Progressive) {
        add("radiusFirst", std::to_string(r.firstRadius));
        add("radiusLast", std::to_string(r.lastRadius));
        add("alpha", std::to_string(s.alpha));
    }
    const std::pair<const char*, double> stages[] = {
        {"photons", r.times.photons}, {"maps", r.times.maps},         {"camera", r.times.camera},
        {"eyePaths", r.times.eyePaths}, {"direct", r.times.direct},   {"caustic", r.times.caustic},
        {"indirect", r.times.indirect}, {"accumulate", r.times.accumulate}};
    for (const auto& [name, sec] : stages) add(std::string("seconds:") + name, std::to_string(sec));
    if (r.stopped) add("interrupted", "after " + std::to_string(r.passes) + " passes");

    Image image = r.film.resolve();
    std::vector<ImageLayer> layers;
    for (const std::string& a : aovs) {
        const Film& f = a == "direct"     ? r.aovs.direct
                        : a == "caustic"  ? r.aovs.caustic
                        : a == "indirect" ? r.aovs.indirect
                        : a == "emitted"  ? r.aovs.emitted
                        : a == "albedo"   ? r.aovs.albedo
                                          : r.aovs.normal;
        layers.push_back({a, f.resolve()});
    }
    std::string written = writeLinearImage(output, image, meta, layers);
    std::string png;
    if (!o.noPng) {
        png = std::filesystem::path(written).replace_extension(".png").string();
        if (!writeSrgbPng(png, image)) png.clear();
    }
    std::fprintf(stderr, "%swrote %s%s%s: %dx%d, %u passes × %u samples/pixel, %.2fs\n",
                 r.stopped ? "interrupted: " : "", written.c_str(), png.empty() ? "" : " and ", png.c_str(),
                 image.width, image.height, r.passes, s.strata * s.strata, seconds);
    if (!o.quiet)
        std::fprintf(stderr, "photons: %llu global, %llu caustic emitted over %u passes\ntime by stage:\n%s",
                     static_cast<unsigned long long>(r.globalEmitted), static_cast<unsigned long long>(r.causticEmitted),
                     r.passes, r.times.table().c_str());
    if (r.nonFiniteSamples)
        std::fprintf(stderr, "warning: %llu non-finite eye samples were dropped\n",
                     static_cast<unsigned long long>(r.nonFiniteSamples));
    return kExitOk;
}

int runRender(const RenderOptions& o) {
    const bool path = o.method == "path";
    // First, before PoCL or the path tracer start threads (they inherit the blocked mask): a
    // Ctrl-C from here on stops a photon render after the current pass, kernel builds included.
    gStop = &watchInterrupts(!path);
    if (path && o.device != "cpu" && o.device != "ref" && o.device != "auto")
        throw InputError("render: --method path runs on the CPU reference (--device ref); got --device " + o.device);
    std::string output = o.output.empty() ? defaultOutput(o.scene) : o.output;
    auto outDir = std::filesystem::path(output).parent_path();
    if (!outDir.empty() && !std::filesystem::is_directory(outDir))
        throw InputError(output + ": output folder does not exist");

    Scene scene = loadScene(o.scene);
    // One of --width/--height alone keeps the camera's aspect ratio.
    const Camera& cam = scene.camera;
    int width = o.width > 0 ? o.width : (o.height > 0 ? std::max(1, o.height * cam.width / cam.height) : cam.width);
    int height = o.height > 0 ? o.height : (o.width > 0 ? std::max(1, o.width * cam.height / cam.width) : cam.height);
    scene.camera.width = width;
    scene.camera.height = height;

    auto start = std::chrono::steady_clock::now();
    SceneGeometry geometry = SceneGeometry::build(scene);
    if (!o.quiet)
        std::fprintf(stderr, "scene %s: %zu triangles, %zu spheres, %zu lights; BVH %zu nodes in %.2fs\n",
                     o.scene.c_str(), scene.triangleCount(), scene.spheres.size(), scene.lights.size(),
                     geometry.stats().nodes, geometry.stats().buildSeconds);
    if (!path) return runPhotonRender(o, scene, geometry, output, start);

    // The plan (photoncl analyze) decides which maps and samplers a render uses. The path
    // tracer builds no photon maps; its lens and time samplers follow the camera and the motion
    // in the scene exactly as the plan's do.
    SceneBuffers buffers = buildSceneBuffers(scene, geometry);
    buildProjectionMaps(scene, geometry, buffers);
    LightPaths paths = classifyLightPaths(scene, geometry, buffers);
    RenderPlan plan = makePlan(scene, paths);
    if (!o.quiet)
        std::fprintf(stderr, "%smethod %s: reference path tracer, no photon maps\n",
                     formatPlan(scene, paths, plan).c_str(), o.method.c_str());
    return runPathTracer(o, scene, geometry, output, start);
}

}  // namespace

Run addRenderCommand(CLI::App& app) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* sub = app.add_subcommand(
        "render",
        "Render a scene to a linear EXR (with metadata) and an sRGB PNG.\n"
        "Options left out are chosen for a clean image in about a minute on a 2-core CPU; the log says which and why.\n"
        "Ctrl-C finishes the current pass and writes the image of the passes done.");
    sub->add_option("SCENE", o->scene, "Scene file (.json, .gltf, .glb)")->required();
    sub->add_option("-o,--output", o->output, "Output EXR (default: <scene name>.exr here); the PNG goes beside it");
    sub->add_option("--method", o->method,
                    "fg: photon mapping with final gathering (direct light by shadow rays, caustics from the caustic "
                    "map, indirect light by gather rays into the global map); direct: the global map read at the "
                    "first diffuse hit (fast preview); progressive: fresh photons every pass, fixed-radius estimates "
                    "whose radius shrinks as r²_{i+1} = r²_i (i+α)/(i+1), converging to the reference; path: the CPU "
                    "reference path tracer")
        ->check(CLI::IsMember({"fg", "direct", "progressive", "path"}))
        ->capture_default_str();
    sub->add_option("--device", o->device,
                    "OpenCL device for the photon methods: cpu (PoCL), gpu, auto, <index> or <name substring> "
                    "(photoncl devices lists them); ref: the CPU reference, for --method path only")
        ->capture_default_str();
    auto passes = sub->add_option("--passes", o->passes,
                                  "Passes (each: fresh photons and eye samples); --method path: samples per pixel "
                                  "(default 64)")
                      ->check(CLI::PositiveNumber);
    sub->add_option("--time", o->seconds, "Render passes for this many seconds instead of a pass count")
        ->check(CLI::PositiveNumber)
        ->excludes(passes);
    sub->add_option("--width", o->width, "Image width (default: the scene camera's)")->check(CLI::PositiveNumber);
    sub->add_option("--height", o->height, "Image height (default: keeps the aspect ratio)")->check(CLI::PositiveNumber);
    sub->add_option("--seed", o->seed, "Random seed: same seed, same device, same image bits")->capture_default_str();
    sub->add_option("--strata", o->strata, "n: n×n stratified eye samples per pixel per pass (1..16)")
        ->check(CLI::Range(1u, 16u));
    sub->add_option("--global-photons", o->globalPhotons, "Photons emitted per pass for the global map")
        ->check(CLI::Range(1u, 2000000000u));
    sub->add_option("--caustic-photons", o->causticPhotons, "Photons emitted per pass for the caustic map")
        ->check(CLI::Range(1u, 2000000000u));
    sub->add_option("--k", o->k, "Photons per global-map estimate (1..500)")->check(CLI::Range(1u, 500u));
    sub->add_option("--caustic-k", o->causticK, "Photons per caustic estimate (1..500)")->check(CLI::Range(1u, 500u));
    sub->add_option("--gather-rays", o->gatherRays, "fg: final-gather rays per diffuse eye hit")
        ->check(CLI::Range(1u, 4096u));
    sub->add_option("--light-samples", o->lightSamples, "Area-light samples (shadow rays) per diffuse eye hit")
        ->check(CLI::Range(1u, 256u));
    sub->add_option("--gather-source", o->gatherSource,
                    "fg: where gather rays read the global map: precomputed (Christensen's precomputed irradiance, "
                    "one lookup per ray) or estimate (the full k-nearest estimate)")
        ->check(CLI::IsMember({"precomputed", "estimate"}))
        ->capture_default_str();
    sub->add_option("--gather-importance", o->histogramCells,
                    "fg: G > 0 importance-samples the gather rays by the incident flux of the k nearest global "
                    "photons on a GxG histogram (Jensen 1995), mixed with the cosine density; 0: cosine only")
        ->check(CLI::Range(0u, 16u))
        ->capture_default_str();
    sub->add_flag("--visibility", o->visibility,
                  "Estimates also reject photons hidden from the shaded point (a shadow ray per photon): no light "
                  "through walls thinner than the search radius; fg then reads the full estimate, not precomputed "
                  "irradiance (slower)");
    sub->add_option("--filter", o->filter, "fg/direct estimate filter: box, cone, epanechnikov, gaussian")
        ->check(CLI::IsMember({"box", "cone", "epanechnikov", "gaussian"}))
        ->capture_default_str();
    sub->add_option("--structure", o->structure,
                    "Search structure of the photon maps: kd-tree or hash-grid (the same photons are found; "
                    "only the speed differs, see `photoncl sweep`)")
        ->check(CLI::IsMember({"kd-tree", "hash-grid"}))
        ->capture_default_str();
    sub->add_option("--max-radius", o->maxRadius, "Largest photon search radius (default: 5 % of the scene's diagonal)")
        ->check(CLI::PositiveNumber);
    sub->add_option("--radius", o->radius,
                    "progressive: the first pass's radius (default: about 20 photons per disc at the mean density)")
        ->check(CLI::PositiveNumber);
    sub->add_option("--alpha", o->alpha, "progressive: α in (0,1) of the radius schedule (Knaus & Zwicker 2011)")
        ->check(CLI::Range(0.01f, 0.99f))
        ->capture_default_str();
    sub->add_option("--aov", o->aov,
                    "Extra EXR layers, comma-separated: direct, caustic, indirect, emitted, albedo, normal "
                    "(photon methods)");
    sub->add_option("--threads", o->threads, "CPU threads of --method path (default: all cores)");
    sub->add_flag("--no-png", o->noPng, "Write only the EXR");
    addMaxBufferMibOption(sub, o->maxBufferMib,
                          "Cap every OpenCL buffer at this many MiB (photon methods; smaller batches, same image; "
                          "--method path allocates none)");
    sub->add_flag("-q,--quiet", o->quiet, "No progress output");
    return [o] { return runRender(*o); };
}

}  // namespace pcl::cli
