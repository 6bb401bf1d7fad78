#include <cstdio>
#include <memory>
#include <string>

#include "cli/command.h"
#include "cli/memory_option.h"
#include "core/error.h"
#include "device/device.h"
#include "pipeline/memory_plan.h"
#include "prep/prepared_scene.h"
#include "scene/load_scene.h"

namespace pcl::cli {

Run addAnalyzeCommand(CLI::App& app) {
    struct Options {
        std::string scene;
        PlanSettings settings;
        uint64_t maxBufferMib = 0;
    };
    auto o = std::make_shared<Options>();
    CLI::App* sub = app.add_subcommand(
        "analyze", "Light paths the scene can produce (L(S|D)*E) and the plan: maps built and samplers used");
    sub->add_option("SCENE", o->scene, "Scene file (.json, .gltf, .glb)")->required();
    sub->add_option("--global-photons", o->settings.globalPhotons, "Photons of the global pass when it runs")
        ->check(CLI::Range(1u, 2000000000u))
        ->capture_default_str();
    sub->add_option("--caustic-photons", o->settings.causticPhotons, "Photons of the caustic pass when it runs")
        ->check(CLI::Range(1u, 2000000000u))
        ->capture_default_str();
    addMaxBufferMibOption(sub, o->maxBufferMib,
                          "Also print the memory plan (every device buffer, batches) for this per-buffer cap");
    return [o] {
        Scene scene = loadScene(o->scene);
        const PreparedScene a = prepareScene(scene, o->settings);
        std::fputs(formatPlan(scene, a.paths, a.plan).c_str(), stdout);
        if (o->maxBufferMib) {
            // The memory plan for the default device under the cap (the cap alone without one):
            // the plan's maps, a kd-tree each, one k = 50 search per pixel.
            PhotonPassOptions pass;
            pass.buildGlobal = a.plan.globalMap;
            pass.buildCaustic = a.plan.causticMap;
            pass.globalPhotons = a.plan.globalPhotons;
            pass.causticPhotons = a.plan.causticPhotons;
            MemoryRequest request = photonPassMemoryRequest(a.geometry, a.buffers, pass);
            request.kdTree = true;
            request.queries = size_t(scene.camera.width) * size_t(scene.camera.height);
            request.k = 50;
            MemoryLimits limits;
            try {
                Device device = Device::open("auto");
                applyBufferCap(device, o->maxBufferMib);
                limits = memoryLimits(device.info());
            } catch (const DeviceError&) {
                limits.maxAlloc = size_t(o->maxBufferMib) << 20;
                limits.device = "no OpenCL device (the cap alone)";
                limits.maxAllocSource = formatMiB(limits.maxAlloc) + " (cap from --max-buffer-mib)";
                limits.capped = true;
            }
            const MemoryPlan memory = planMemory(request, limits);
            std::printf("\nsearch planned: one query per pixel (%zu), k = %u\n", request.queries, request.k);
            std::fputs(formatMemoryPlan(memory).c_str(), stdout);
            if (!memory.fits()) return kExitBadInput;
        }
        return kExitOk;
    };
}

}  // namespace pcl::cli
