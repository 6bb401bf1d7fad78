// `photoncl render`: scene file → linear EXR (with metadata, optional AOV layers) + sRGB PNG.
// Methods: fg (photon mapping with final gathering, the default), direct (the global map read at
// the first diffuse hit: a preview), progressive (probabilistic progressive photon mapping), path
// (the CPU reference path tracer). Options left out get defaults chosen for a clean image in
// about a minute on a 2-core CPU, and the log says what was chosen and why.
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>

#include "cli/command.h"
#include "cli/memory_option.h"
#include "core/clock.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "device/device.h"
#include "image/image_io.h"
#include "pipeline/memory_plan.h"
#include "pipeline/photon_pass.h"
#include "prep/environment_map.h"
#include "prep/media_support.h"
#include "prep/prepared_scene.h"
#include "render/auto_method.h"
#include "render/path_render.h"
#include "render/photon_renderer.h"
#include "render/render_settings.h"
#include "scene/load_scene.h"

namespace pcl::cli {
namespace {

struct RenderOptions {
    std::string scene, output, device = "cpu";
    RenderRequest request;  // method, counts, names: resolved by render/render_settings
    int width = 0, height = 0;
    int threads = 0;
    bool quiet = false, noPng = false;
    bool noLightTracing = false;  // --no-light-tracing: the path tracer alone
    bool methodGiven = false;     // --method was on the command line (else auto, or as defaultMethod says)
    std::string photonOption;     // the first option given that only the photon methods read ("--aov"), if any
    uint64_t maxBufferMib = 0;    // --max-buffer-mib: applyBufferCap on the OpenCL device
    std::string aov;
    bool profile = false;
};

std::string defaultOutput(const std::string& scenePath) {
    return std::filesystem::path(scenePath).stem().string() + ".exr";
}

// Ctrl-C (or SIGTERM): the render finishes the pass it is in and writes the passes done
// (core/interrupt.h); the path tracer, which cannot stop between passes, quits at once.
const std::atomic<bool>* gStop = nullptr;

int runPathTracer(const RenderOptions& o, const Scene& scene, const SceneGeometry& geometry, const std::string& output,
                  Clock::time_point start) {
    const RenderRequest& q = o.request;
    PathRenderSettings settings;
    settings.seed = q.seed;
    settings.threads = o.threads;
    settings.seconds = q.seconds;
    settings.samples = q.passes ? q.passes : (q.seconds > 0 ? 0 : 64);
    settings.lightTracing = !o.noLightTracing;
    settings.stop = gStop;  // set only under auto (graceful interrupts): --method path exits at the first Ctrl-C
    Progress progress("render", !o.quiet);
    settings.progress = [&](uint32_t, double f) { progress.update(f); };
    PathRenderResult r = renderPathTraced(scene, geometry, settings);
    progress.finish();
    double seconds = since(start);

    ImageMetadata meta;
    meta.scene = o.scene;
    meta.method = q.method;
    meta.device = "ref";
    meta.samples = static_cast<int64_t>(r.samples);
    meta.seed = q.seed;
    meta.seconds = seconds;
    Image image = r.film.resolve();
    std::string written = writeLinearImage(output, image, meta);
    std::string png;
    if (!o.noPng) {
        png = std::filesystem::path(written).replace_extension(".png").string();
        if (!writeSrgbPng(png, image)) png.clear();
    }
    double sps = r.seconds > 0 ? r.paths / r.seconds : 0.0;
    std::fprintf(stderr, "%swrote %s%s%s: %dx%d, %u samples/pixel, %.2fs, %.3g samples/s\n",
                 r.stopped ? "interrupted: " : "", written.c_str(), png.empty() ? "" : " and ", png.c_str(),
                 image.width, image.height, r.samples, seconds, sps);
    if (!r.lightTracing.empty() && !o.quiet)
        std::fprintf(stderr,
                     "light tracer: %s, so every sample per pixel also traced %.3g light paths aimed from the delta "
                     "lights at the mirrors and glass (%.3g in all, %.3g connections to the camera); "
                     "--no-light-tracing: the path tracer alone\n",
                     r.lightTracing.c_str(), r.samples ? double(r.lightPaths) / r.samples : 0.0, double(r.lightPaths),
                     double(r.lightSplats));
    if (r.discarded)
        std::fprintf(stderr, "warning: %llu non-finite path samples were discarded\n",
                     static_cast<unsigned long long>(r.discarded));
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
            throw InputError("render: --aov " + item +
                             ": expected a comma-separated list of direct, caustic, indirect, "
                             "emitted, albedo, normal");
        out.push_back(item);
    }
    return out;
}

std::string kernelProfileTable(const std::vector<Device::KernelTime>& profile, uint32_t passes) {
    double total = 0.0;
    for (const Device::KernelTime& k : profile) total += k.seconds;
    std::string out = "device time by kernel (seconds per pass, launches per pass):\n";
    char line[160];
    const double p = std::max(passes, 1u);
    for (const Device::KernelTime& k : profile) {
        std::snprintf(line, sizeof line, "  %-36s %9.4f s  %5.1f %%  %7.1f\n", k.kernel.c_str(), k.seconds / p,
                      total > 0 ? 100.0 * k.seconds / total : 0.0, k.launches / p);
        out += line;
    }
    std::snprintf(line, sizeof line, "  %-36s %9.4f s\n", "all kernels", total / p);
    return out + line;
}

// The photon pass per pass (issue 14's paths per second inside render): the first pass apart,
// since it also loads the kernels and touches fresh buffers. Milliseconds in fixed point: never
// an exponent, whatever the pass takes.
std::string photonPassProfile(const std::vector<double>& seconds, uint64_t paths) {
    if (seconds.empty() || paths == 0) return {};
    const double perPass = double(paths) / double(seconds.size());
    char line[200];
    if (seconds.size() == 1) {
        std::snprintf(line, sizeof line, "photon pass: %.3f ms, %.3g M paths a second\n", seconds[0] * 1e3,
                      perPass / seconds[0] * 1e-6);
        return line;
    }
    std::vector<double> later(seconds.begin() + 1, seconds.end());
    std::sort(later.begin(), later.end());
    const size_t n = later.size();
    const double median = n % 2 ? later[n / 2] : 0.5 * (later[n / 2 - 1] + later[n / 2]);
    std::snprintf(line, sizeof line,
                  "photon pass: first pass %.3f ms, later passes median %.3f ms (%.3f-%.3f): %.3g M paths a "
                  "second\n",
                  seconds[0] * 1e3, median * 1e3, later.front() * 1e3, later.back() * 1e3,
                  median > 0 ? perPass / median * 1e-6 : 0.0);
    return line;
}

// `device`: already opened (method auto's pilot ran on it), else opened here.
int runPhotonRender(const RenderOptions& o, const Scene& scene, const PreparedScene& prepared,
                    const std::string& output, Clock::time_point start, std::unique_ptr<Device> device = nullptr) {
    const RenderRequest& q = o.request;
    // --device ref: the whole render on the CPU twin's stages (host/reference), no OpenCL.
    const bool twin = o.device == "ref";
    if (twin && o.profile)
        throw InputError("render: --profile times OpenCL kernels; --device ref (the CPU twin) runs none");
    if (twin && o.maxBufferMib)
        throw InputError("render: --max-buffer-mib caps an OpenCL device's buffers; --device ref (the CPU twin) has "
                         "none");
    std::vector<std::string> aovs = parseAovs(o.aov);
    const SceneGeometry& geometry = prepared.geometry;
    const SceneBuffers& buffers = prepared.buffers;
    const RenderPlan& plan = prepared.plan;
    ResolvedSettings resolved = resolveRenderSettings(q, plan, scene.camera.width, scene.camera.height);
    PhotonRenderSettings& s = resolved.settings;
    s.aovs = !aovs.empty();
    s.stop = gStop;

    std::string deviceName = "ref", platform = "CPU twin (host/reference)";
    if (!twin) {
        if (!device) device = std::make_unique<Device>(Device::open(o.device));
        applyBufferCap(*device, o.maxBufferMib);
        device->setProfiling(o.profile);
        // The memory plan for one pass's photon maps, before any work (fails early with advice).
        s.photonBatch = planRenderMemory(device->info(), geometry, buffers, s, plan).photonBatch;
        deviceName = device->info().name;
        platform = device->info().platform;
    }

    if (!o.quiet) {
        std::fprintf(stderr, "%s", formatPlan(scene, prepared.paths, plan).c_str());
        std::fprintf(stderr, "render %s with %s on %s (%s):\n%s", o.scene.c_str(), q.method.c_str(), deviceName.c_str(),
                     platform.c_str(), resolved.log().c_str());
    }
    Progress progress("render", !o.quiet);
    s.onPass = [&](uint32_t, double fraction) { progress.update(fraction); };
    PhotonRenderResult r = twin ? renderPhotonMappedTwin(scene, geometry, buffers, plan, s)
                                : renderPhotonMapped(*device, scene, geometry, buffers, plan, s);
    progress.finish();
    double seconds = since(start);

    ImageMetadata meta;
    meta.scene = o.scene;
    meta.method = q.method;
    meta.device = deviceName;
    meta.samples = static_cast<int64_t>(r.passes) * s.strata * s.strata;
    meta.seed = q.seed;
    meta.seconds = seconds;
    auto add = [&](const std::string& k, const std::string& v) { meta.extra.emplace_back(k, v); };
    // Exactly what a batch shard of these passes records (render_settings.h), then the summary.
    const std::string text = settingsText(s, plan, scene.camera.width, scene.camera.height, r.passes);
    add("settings", text);
    add("settingsHash", hex64(settingsHash(text)));
    add("summary", r.summary);
    add("passes", std::to_string(r.passes));
    add("globalPhotonsEmitted", std::to_string(r.globalEmitted));
    add("causticPhotonsEmitted", std::to_string(r.causticEmitted));
    add("globalPhotonsStored", std::to_string(r.globalStored));
    add("causticPhotonsStored", std::to_string(r.causticStored));
    add("platform", platform);
    if (s.method == RenderMethod::Progressive) {
        add("radiusFirst", std::to_string(r.firstRadius));
        add("radiusLast", std::to_string(r.lastRadius));
        add("alpha", std::to_string(s.alpha));
    }
    const std::pair<const char*, double> stages[] = {
        {"photons", r.times.photons},   {"maps", r.times.maps},
        {"camera", r.times.camera},     {"eyePaths", r.times.eyePaths},
        {"direct", r.times.direct},     {"caustic", r.times.caustic},
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
                     static_cast<unsigned long long>(r.globalEmitted),
                     static_cast<unsigned long long>(r.causticEmitted), r.passes, r.times.table().c_str());
    if (!o.quiet && r.emitterPixels)
        std::fprintf(stderr, "emitter samples: %ux%u a pass in %u pixels (the rows' spans of emitter edges)\n",
                     r.emitterStrata, r.emitterStrata, r.emitterPixels);
    if (o.profile)
        std::fprintf(stderr, "%s%s", kernelProfileTable(device->kernelProfile(), r.passes).c_str(),
                     photonPassProfile(r.photonPassSeconds, r.globalEmitted + r.causticEmitted).c_str());
    if (r.nonFiniteSamples)
        std::fprintf(stderr, "warning: %llu non-finite eye samples were dropped\n",
                     static_cast<unsigned long long>(r.nonFiniteSamples));
    return kExitOk;
}

// --method auto: the pilot (render/auto_method.h) picks fg or the path tracer; a time budget
// pays for the pilot.
int runAutoMethod(const RenderOptions& o, const Scene& scene, const PreparedScene& prepared, const std::string& output,
                  Clock::time_point start) {
    if (o.device == "ref")
        throw InputError("render: --method auto pilots fg on an OpenCL device; with --device ref give --method");
    auto device = std::make_unique<Device>(Device::open(o.device));
    const AutoMethodChoice choice = chooseRenderMethod(*device, scene, prepared, o.request);
    std::fprintf(stderr, "%s", choice.log().c_str());
    RenderOptions chosen = o;
    chosen.request = choice.best().request;
    if (o.request.seconds > 0) {
        chosen.request.seconds = std::max(0.1, o.request.seconds - choice.pilotSeconds);
    } else if (!o.request.passes) {
        chosen.request.passes = choice.unitsWithoutBudget(scene.camera.width, scene.camera.height);
        if (!o.quiet)
            std::fprintf(stderr,
                         "method auto: no --time: %u %s, about %.0f s (fg's default passes, as the pilot "
                         "predicts them)\n",
                         chosen.request.passes, chosen.request.method == "path" ? "samples per pixel" : "passes",
                         choice.fgBudgetSeconds(scene.camera.width, scene.camera.height));
    }
    if (chosen.request.method == "path") {
        if (!o.quiet) std::fprintf(stderr, "%s", formatPlan(scene, prepared.paths, prepared.plan).c_str());
        return runPathTracer(chosen, scene, prepared.geometry, output, start);
    }
    return runPhotonRender(chosen, scene, prepared, output, start, std::move(device));
}

// The method of a render that names none: auto, unless the command line or the scene says
// what auto's pilot cannot weigh. Empty reason: auto, which logs its own choice.
struct DefaultMethod {
    std::string method, reason;
};
DefaultMethod defaultMethod(const RenderOptions& o, const Scene& scene) {
    if (scene.hasMedia())
        return {"progressive",
                "the scene has participating media, which fg's gather rays do not carry yet (--method to choose)"};
    if (o.device == "ref")
        return {"fg", "--device ref runs the photon methods' CPU twins (auto's pilot needs an OpenCL device)"};
    if (o.request.passes)
        return {"fg", "--passes counts passes of a photon method (--method auto with --time lets a pilot choose)"};
    if (!o.photonOption.empty())
        return {"fg", o.photonOption + " is an option of the photon methods (--method to choose another)"};
    return {"auto", ""};
}

int runRender(const RenderOptions& given) {
    RenderOptions o = given;
    const RenderRequest& q = o.request;
    const bool path = q.method == "path";
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
    if (!o.methodGiven) {
        const DefaultMethod d = defaultMethod(o, scene);
        if (!o.quiet && !d.reason.empty()) std::fprintf(stderr, "method %s: %s\n", d.method.c_str(), d.reason.c_str());
        o.request.method = d.method;
    } else if (q.method == "auto" && scene.hasMedia()) {
        // auto's pilot weighs fg against the path tracer, and fg refuses media.
        if (!o.quiet)
            std::fprintf(stderr, "method auto: progressive: the scene has participating media, which fg's gather rays "
                                 "do not carry yet (--method to choose)\n");
        o.request.method = "progressive";
    }
    // One of --width/--height alone keeps the camera's aspect ratio.
    const Camera& cam = scene.camera;
    int width = o.width > 0 ? o.width : (o.height > 0 ? std::max(1, o.height * cam.width / cam.height) : cam.width);
    int height = o.height > 0 ? o.height : (o.width > 0 ? std::max(1, o.width * cam.height / cam.width) : cam.height);
    scene.camera.width = width;
    scene.camera.height = height;

    const Clock::time_point start = Clock::now();
    // The plan (photoncl analyze) decides which maps and samplers a render uses. The path
    // tracer builds no photon maps; its lens and time samplers follow the camera and the motion
    // in the scene exactly as the plan's do.
    const PreparedScene prepared = prepareScene(scene, planSettingsFor(q.method));
    if (!o.quiet)
        std::fprintf(stderr, "scene %s: %zu triangles, %zu spheres, %zu lights; BVH %zu nodes in %.2fs\n",
                     o.scene.c_str(), scene.triangleCount(), scene.spheres.size(), scene.lights.size(),
                     prepared.geometry.stats().nodes, prepared.geometry.stats().buildSeconds);
    if (q.method == "fg") refuseMediaWithoutPathTracer(scene, "--method fg (fg's gather rays do not carry media yet)");
    if (!path) refuseEnvironmentInMediaWithoutPathTracer(scene, "--method " + q.method);
    if (q.method == "auto") return runAutoMethod(o, scene, prepared, output, start);
    if (!path) return runPhotonRender(o, scene, prepared, output, start);
    if (!o.quiet)
        std::fprintf(stderr, "%smethod %s: reference path tracer, no photon maps\n",
                     formatPlan(scene, prepared.paths, prepared.plan).c_str(), q.method.c_str());
    return runPathTracer(o, scene, prepared.geometry, output, start);
}

}  // namespace

Run addRenderCommand(CLI::App& app) {
    auto o = std::make_shared<RenderOptions>();
    o->request.method = "auto";
    CLI::App* sub = app.add_subcommand(
        "render",
        "Render a scene to a linear EXR (with metadata) and an sRGB PNG.\n"
        "Options left out are chosen for a clean image in about a minute on a 2-core CPU; the log says which and why.\n"
        "Ctrl-C finishes the current pass and writes the image of the passes done.");
    sub->add_option("SCENE", o->scene, "Scene file (.json, .gltf, .glb)")->required();
    sub->add_option("-o,--output", o->output, "Output EXR (default: <scene name>.exr here); the PNG goes beside it");
    CLI::Option* methodOption =
        sub->add_option(
               "--method", o->request.method,
               "auto (the default): fg or path, whichever a pilot of each at a quarter of the size (about 2-5 s, "
               "paid from --time) says reaches a lower relMSE in the time (its noise at that time plus, for fg, "
               "its bias against the path tracer's pilot), fg with the gather rays its indirect "
               "part's share of the pilot's variance and time asks for (at most twice the default); without --time "
               "the winner gets the "
               "time fg's default passes would take. Left out, the method is fg instead when --passes, --device ref "
               "or an option only the photon methods read (--aov, --strata, --k, ...) is given, and progressive "
               "in participating media. fg: photon mapping with final gathering (direct light by shadow rays, "
               "caustics from the caustic map, indirect light by gather rays into the global map); direct: the "
               "global map read at the first diffuse hit (fast preview); progressive: fresh photons every pass, "
               "fixed-radius estimates whose radius shrinks as r²_{i+1} = r²_i (i+α)/(i+1), converging to the "
               "reference; path: the CPU reference path tracer. fg refuses media (its gather rays do not carry "
               "them yet); auto renders them progressive")
            ->check(CLI::IsMember({"fg", "direct", "progressive", "path", "auto"}))
            ->capture_default_str();
    sub->add_option("--device", o->device,
                    "OpenCL device for the photon methods: cpu (PoCL), gpu, auto, <index> or <name substring> "
                    "(photoncl devices lists them); ref: the CPU reference, no OpenCL: --method path, or the photon "
                    "methods on the CPU twin of every kernel stage (same seeds and passes as a device render; "
                    "brute-force searches, for small images)")
        ->capture_default_str();
    auto passes = sub->add_option("--passes", o->request.passes,
                                  "Passes (each: fresh photons and eye samples); --method path: samples per pixel "
                                  "(default 64)")
                      ->check(CLI::PositiveNumber);
    sub->add_option("--time", o->request.seconds, "Render passes for this many seconds instead of a pass count")
        ->check(CLI::PositiveNumber)
        ->excludes(passes);
    sub->add_option("--width", o->width, "Image width (default: the scene camera's)")->check(CLI::PositiveNumber);
    sub->add_option("--height", o->height, "Image height (default: keeps the aspect ratio)")
        ->check(CLI::PositiveNumber);
    sub->add_option("--seed", o->request.seed, "Random seed: same seed, same device, same image bits")
        ->capture_default_str();
    sub->add_option("--strata", o->request.strata, "n: n×n stratified eye samples per pixel per pass (1..16)")
        ->check(CLI::Range(1u, 16u));
    sub->add_option("--global-photons", o->request.globalPhotons, "Photons emitted per pass for the global map")
        ->check(CLI::Range(1u, 2000000000u));
    sub->add_option("--caustic-photons", o->request.causticPhotons, "Photons emitted per pass for the caustic map")
        ->check(CLI::Range(1u, 2000000000u));
    sub->add_option("--k", o->request.k, "Photons per global-map estimate (1..500)")->check(CLI::Range(1u, 500u));
    sub->add_option("--caustic-k", o->request.causticK, "Photons per caustic estimate (1..500)")
        ->check(CLI::Range(1u, 500u));
    sub->add_option("--volume-k", o->request.volumeK,
                    "Media: photons per volume radius (the first radius holds about this many; 1..499)")
        ->check(CLI::Range(1u, 499u));
    sub->add_option("--volume-radii", o->request.volumeRadii,
                    "Media: the beam estimate's radii: fixed (one per pass) or photon (each photon's own, from "
                    "its k-th nearest volume photon)")
        ->check(CLI::IsMember({"fixed", "photon"}));
    sub->add_option("--emitter-strata", o->request.emitterStrata,
                    "fg: up to M×M samples per pixel and pass for the light eye paths collect before their diffuse "
                    "hit (lamps seen directly, in mirrors or glossy floors), where a probe saw an emitter's edge; "
                    "fewer when those pixels are many (0: off; default 16)")
        ->check(CLI::Range(0, 16));
    sub->add_option("--caustics", o->request.caustics,
                    "fg: connect (each caustic photon joined to the camera, as a light tracer does: sharp caustics "
                    "where the eye sees them directly; the caustic map only through mirrors and glass; in scenes "
                    "that move, at each photon's shutter time) or map (Jensen's caustic map at every eye hit)")
        ->check(CLI::IsMember({"connect", "map"}));
    sub->add_option("--gather-rays", o->request.gatherRays, "fg: final-gather rays per diffuse eye hit")
        ->check(CLI::Range(1u, 4096u));
    sub->add_option("--light-samples", o->request.lightSamples, "Area-light samples (shadow rays) per diffuse eye hit")
        ->check(CLI::Range(1u, 256u));
    sub->add_option("--gather-source", o->request.gatherSource,
                    "fg: where gather rays read the global map: precomputed (Christensen's precomputed irradiance, "
                    "one lookup per ray) or estimate (the full k-nearest estimate)")
        ->check(CLI::IsMember({"precomputed", "estimate"}))
        ->capture_default_str();
    sub->add_option("--close-gather", o->request.closeGather,
                    "fg: a gather ray whose hit lies within F times the radius of k photons at the mean density "
                    "(its path's length from the eye hit, through mirrors and glass too) "
                    "takes the direct light there by shadow rays and reads only the map's other photons (the "
                    "map's blur hurts most next to the eye hit: contact shadows, shadow edges); 0: off")
        ->check(CLI::Range(0.0f, 100.0f));
    sub->add_option("--gather-importance", o->request.gatherImportance,
                    "fg: G > 0 importance-samples the gather rays by the incident flux of the k nearest global "
                    "photons on a GxG histogram (Jensen 1995), mixed with the cosine density; 0: cosine only")
        ->check(CLI::Range(0u, 16u))
        ->capture_default_str();
    sub->add_flag("--visibility", o->request.visibility,
                  "Estimates also reject photons hidden from the shaded point (a shadow ray per photon): no light "
                  "through walls thinner than the search radius; fg then reads the full estimate, not precomputed "
                  "irradiance (slower)");
    sub->add_option("--filter", o->request.filter, "fg/direct estimate filter: box, cone, epanechnikov, gaussian")
        ->check(CLI::IsMember({"box", "cone", "epanechnikov", "gaussian"}))
        ->capture_default_str();
    sub->add_option("--structure", o->request.structure,
                    "Search structure of the photon maps: kd-tree or hash-grid (the same photons are found; "
                    "only the speed differs, see `photoncl sweep`)")
        ->check(CLI::IsMember({"kd-tree", "hash-grid"}))
        ->capture_default_str();
    sub->add_option("--max-radius", o->request.maxRadius,
                    "Largest photon search radius (default: 5 % of the scene's diagonal)")
        ->check(CLI::PositiveNumber);
    sub->add_option("--radius", o->request.radius,
                    "progressive: the first pass's radius (default: about 20 photons per disc at the mean density)")
        ->check(CLI::PositiveNumber);
    sub->add_option("--alpha", o->request.alpha,
                    "progressive: α in (0,1) of the radius schedule (Knaus & Zwicker 2011)")
        ->check(CLI::Range(0.01f, 0.99f))
        ->capture_default_str();
    sub->add_option("--aov", o->aov,
                    "Extra EXR layers, comma-separated: direct, caustic, indirect, emitted, albedo, normal "
                    "(photon methods)");
    sub->add_option("--threads", o->threads, "CPU threads of --method path (default: all cores)");
    sub->add_flag("--no-png", o->noPng, "Write only the EXR");
    sub->add_flag("--no-light-tracing", o->noLightTracing,
                  "--method path: leave out the light tracer that adds light from point, spot and directional "
                  "lights through mirrors and glass (the path tracer alone misses it, as other path tracers do)");
    addMaxBufferMibOption(sub, o->maxBufferMib,
                          "Cap every OpenCL buffer at this many MiB (photon methods; smaller batches, same image; "
                          "--method path allocates none)");
    sub->add_flag("--profile", o->profile,
                  "Photon methods: after the render, device seconds and launches per kernel (per pass and in all)");
    sub->add_flag("-q,--quiet", o->quiet, "No progress output");
    return [o, methodOption, sub] {
        o->methodGiven = methodOption->count() > 0;
        for (const char* name : {"--strata",
                                 "--global-photons",
                                 "--caustic-photons",
                                 "--k",
                                 "--caustic-k",
                                 "--volume-k",
                                 "--volume-radii",
                                 "--gather-rays",
                                 "--caustics",
                                 "--emitter-strata",
                                 "--light-samples",
                                 "--gather-source",
                                 "--gather-importance",
                                 "--close-gather",
                                 "--visibility",
                                 "--filter",
                                 "--structure",
                                 "--max-radius",
                                 "--radius",
                                 "--alpha",
                                 "--aov",
                                 "--profile",
                                 "--max-buffer-mib"})
            if (o->photonOption.empty() && sub->get_option(name)->count() > 0) o->photonOption = name;
        return runRender(*o);
    };
}

}  // namespace pcl::cli
