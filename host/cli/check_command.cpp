#include <cstdio>
#include <memory>
#include <string>

#include "cli/command.h"
#include "cli/memory_option.h"
#include "core/error.h"
#include "device/device.h"
#include "pipeline/check_estimate.h"
#include "pipeline/check_intersect.h"
#include "pipeline/check_irradiance.h"
#include "pipeline/check_knn.h"
#include "pipeline/check_render.h"
#include "pipeline/check_maps.h"
#include "pipeline/check_photons.h"
#include "scene/load_scene.h"

namespace pcl::cli {

Run addCheckCommand(CLI::App& app) {
    struct Options {
        std::string scene, device = "auto", stage = "all";
        size_t rays = 100000;
        uint32_t photons = 50000;
        uint64_t seed = 1;
        uint64_t maxBufferMib = 0;
    };
    auto o = std::make_shared<Options>();
    CLI::App* sub = app.add_subcommand(
        "check", "Run kernel stages and their CPU twins on the same inputs and compare them");
    sub->add_option("SCENE", o->scene, "Scene file (.json, .gltf, .glb)")->required();
    sub->add_option("--device", o->device, "OpenCL device: auto|cpu|gpu|<index>|<name substring>")
        ->capture_default_str();
    sub->add_option("--stage", o->stage,
                    "trace: BVH traversal; emit, trace_photons, deposit: the photon pass stage by stage on the "
                    "same inputs; pass: the whole photon pass; sort: device radix sort; build: kd-tree; knn: k nearest "
                    "neighbours on kd-tree and hash grid against brute force; estimate: the filtered irradiance "
                    "estimate (every filter, both structures, with and without the visibility test) and the "
                    "precomputed irradiance lookup; render: the eye pass (camera, eye paths, direct light, caustics, final "
                    "gather, direct visualisation) per stage and per pixel on a small image; all: every one")
        ->check(CLI::IsMember(
            {"all", "trace", "emit", "trace_photons", "deposit", "pass", "sort", "build", "knn", "estimate", "render"}))
        ->capture_default_str();
    sub->add_option("--rays", o->rays, "Rays for the trace check")->capture_default_str();
    sub->add_option("--photons", o->photons, "Photon paths per pass for the photon checks")->capture_default_str();
    sub->add_option("--seed", o->seed, "Seed of the random inputs")->capture_default_str();
    addMaxBufferMibOption(sub, o->maxBufferMib, "Cap every device buffer at this many MiB (the stages split their work)");
    return [o] {
        if (o->device == "ref") throw InputError("check: --device ref has no kernels to check; pick an OpenCL device");
        Scene scene = loadScene(o->scene);
        Device device = Device::open(o->device);
        applyBufferCap(device, o->maxBufferMib);
        std::printf("check %s on %s (%s)\n", o->scene.c_str(), device.info().name.c_str(),
                    device.info().platform.c_str());
        bool ok = true;
        if (o->stage == "all" || o->stage == "trace") {
            IntersectCheckReport report = checkIntersect(device, scene, o->rays, o->seed);
            std::printf("stage trace: kernel vs host BVH traversal\n%s", report.table().c_str());
            std::printf("stage trace: %s\n", report.passed() ? "PASSED" : "FAILED");
            ok = ok && report.passed();
        }
        PhotonCheckOptions photonOptions;
        photonOptions.photons = o->photons;
        photonOptions.seed = o->seed;
        for (const char* stage : {"emit", "trace_photons", "deposit", "pass"}) {
            if (o->stage != "all" && o->stage != stage) continue;
            // The photon tracing stage is "trace" inside the photon check (its own name space).
            std::string inner = std::string(stage) == "trace_photons" ? "trace" : stage;
            PhotonCheckReport report = checkPhotonStage(device, scene, inner, photonOptions);
            std::printf("stage %s: kernel vs CPU twin\n%s", stage, report.table().c_str());
            std::printf("stage %s: %s\n", stage, report.passed() ? "PASSED" : "FAILED");
            ok = ok && report.passed();
        }
        auto print = [&](const char* stage, const std::string& table, bool passed) {
            std::printf("stage %s: kernel vs CPU twin\n%s", stage, table.c_str());
            std::printf("stage %s: %s\n", stage, passed ? "PASSED" : "FAILED");
            ok = ok && passed;
        };
        MapCheckOptions mapOptions;
        mapOptions.photons = o->photons;
        mapOptions.seed = o->seed;
        if (o->stage == "all" || o->stage == "sort") {
            MapCheckReport r = checkSort(device, scene, mapOptions);
            print("sort", r.table(), r.passed());
        }
        if (o->stage == "all" || o->stage == "build") {
            MapCheckReport r = checkKdTreeBuild(device, scene, mapOptions);
            print("build", r.table(), r.passed());
        }
        if (o->stage == "all" || o->stage == "knn") {
            KnnCheckOptions knnOptions;
            knnOptions.photons = o->photons;
            knnOptions.seed = o->seed;
            KnnCheckReport r = checkKnn(device, scene, knnOptions);
            print("knn", r.table(), r.passed());
        }
        if (o->stage == "all" || o->stage == "estimate") {
            EstimateCheckOptions estimateOptions;
            estimateOptions.photons = o->photons;
            estimateOptions.seed = o->seed;
            EstimateCheckReport r = checkEstimate(device, scene, estimateOptions);
            print("estimate", r.table(), r.passed());
            IrradianceCheckOptions irradianceOptions;
            irradianceOptions.photons = o->photons;
            irradianceOptions.seed = o->seed;
            IrradianceCheckReport ir = checkPrecomputedIrradiance(device, scene, irradianceOptions);
            print("estimate (precomputed irradiance)", ir.table(), ir.passed());
        }
        if (o->stage == "all" || o->stage == "render") {
            RenderCheckOptions renderOptions;
            renderOptions.seed = o->seed;
            RenderCheckReport r = checkRender(device, scene, renderOptions);
            print("render", r.table(), r.passed());
        }
        return ok ? kExitOk : kExitCheckFailed;
    };
}

}  // namespace pcl::cli
