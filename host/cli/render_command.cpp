// `photoncl render`: scene file → linear EXR (with metadata) + sRGB PNG. Until the photon-mapping
// stages land, the only method is the reference path tracer (`--method path`, CPU).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include "cli/command.h"
#include "cli/memory_option.h"
#include "core/error.h"
#include "core/progress.h"
#include "geometry/scene_geometry.h"
#include "image/image_io.h"
#include "pipeline/plan.h"
#include "pipeline/projection_map.h"
#include "pipeline/scene_buffers.h"
#include "reference/path_tracer.h"
#include "scene/load_scene.h"

namespace pcl::cli {
namespace {

struct RenderOptions {
    std::string scene, output, device = "auto", method = "path";
    int passes = 0;        // samples per pixel; 0: the default for the method
    double seconds = 0.0;  // time budget instead of a pass count
    int width = 0, height = 0;
    uint64_t seed = 0;
    int threads = 0;
    bool quiet = false, noPng = false;
    uint64_t maxBufferMib = 0;  // --max-buffer-mib: for the OpenCL methods (applyBufferCap on their Device)
};

std::string defaultOutput(const std::string& scenePath) {
    return std::filesystem::path(scenePath).stem().string() + ".exr";
}

int runRender(const RenderOptions& o) {
    if (o.device != "auto" && o.device != "ref")
        throw InputError("render: --method " + o.method + " runs on the CPU reference (--device ref); got --device " +
                         o.device + " (OpenCL rendering arrives with the photon-mapping stages)");
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

}  // namespace

Run addRenderCommand(CLI::App& app) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* sub = app.add_subcommand("render", "Render a scene to a linear EXR (with metadata) and an sRGB PNG");
    sub->add_option("SCENE", o->scene, "Scene file (.json, .gltf, .glb)")->required();
    sub->add_option("-o,--output", o->output, "Output EXR (default: <scene name>.exr here); the PNG goes beside it");
    sub->add_option("--device", o->device, "auto|ref|cpu|gpu|<index>|<name substring>")->capture_default_str();
    sub->add_option("--method", o->method, "path: reference path tracer (photon mapping arrives later)")
        ->check(CLI::IsMember({"path"}))
        ->capture_default_str();
    auto passes = sub->add_option("--passes", o->passes, "Samples per pixel (default 64)")->check(CLI::PositiveNumber);
    sub->add_option("--time", o->seconds, "Render for this many seconds instead of a pass count")
        ->check(CLI::PositiveNumber)
        ->excludes(passes);
    sub->add_option("--width", o->width, "Image width (default: the scene camera's)")->check(CLI::PositiveNumber);
    sub->add_option("--height", o->height, "Image height (default: keeps the aspect ratio)")->check(CLI::PositiveNumber);
    sub->add_option("--seed", o->seed, "Random seed: same seed, same image bits")->capture_default_str();
    sub->add_option("--threads", o->threads, "CPU threads (default: all cores)");
    sub->add_flag("--no-png", o->noPng, "Write only the EXR");
    addMaxBufferMibOption(sub, o->maxBufferMib,
                          "Cap every OpenCL buffer at this many MiB (photon-mapping methods; --method path allocates "
                          "none)");
    sub->add_flag("-q,--quiet", o->quiet, "No progress output");
    return [o] { return runRender(*o); };
}

}  // namespace pcl::cli
