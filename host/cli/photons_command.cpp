// `photoncl photons`: runs the plan's photon pass on an OpenCL device and writes the maps as a
// PLY point cloud (host/pipeline/photon_ply.h) for viewing and diffing between devices.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "cli/command.h"
#include "cli/memory_option.h"
#include "core/error.h"
#include "device/device.h"
#include "pipeline/memory_plan.h"
#include "pipeline/photon_pass.h"
#include "pipeline/photon_ply.h"
#include "prep/environment_map.h"
#include "prep/media_support.h"
#include "prep/prepared_scene.h"
#include "scene/load_scene.h"

namespace pcl::cli {
namespace {

struct PhotonsOptions {
    std::string scene, output, device = "auto", map = "both";
    PlanSettings settings;
    uint64_t seed = 1;
    bool ascii = false;
    uint64_t maxBufferMib = 0;  // --max-buffer-mib; 0: the driver's limit
};

int runPhotons(const PhotonsOptions& o) {
    if (o.device == "ref")
        throw InputError("photons: --device ref has no photon kernels; pick an OpenCL device (auto|cpu|gpu|...)");
    auto outDir = std::filesystem::path(o.output).parent_path();
    if (!outDir.empty() && !std::filesystem::is_directory(outDir))
        throw InputError(o.output + ": output folder " + outDir.string() + " does not exist");

    Scene scene = loadScene(o.scene);
    refuseMediaWithoutPathTracer(scene, "photons (the photon pass)");
    refuseEnvironmentInMediaWithoutPathTracer(scene, "photons (the photon pass)");
    const PreparedScene prepared = prepareScene(scene, o.settings);
    const SceneGeometry& geometry = prepared.geometry;
    const SceneBuffers& buffers = prepared.buffers;
    const RenderPlan& plan = prepared.plan;

    // The plan decides which maps the scene needs; --map narrows that choice.
    const bool wantGlobal = o.map != "caustic", wantCaustic = o.map != "global";
    PhotonPassOptions pass;
    pass.buildGlobal = plan.globalMap && wantGlobal;
    pass.buildCaustic = plan.causticMap && wantCaustic;
    pass.globalPhotons = pass.buildGlobal ? plan.globalPhotons : 0;
    pass.causticPhotons = pass.buildCaustic ? plan.causticPhotons : 0;
    pass.seed = o.seed;
    if (wantGlobal && !plan.globalMap)
        std::fprintf(stderr, "photons: the plan builds no global map for %s; none written\n", o.scene.c_str());
    if (wantCaustic && !plan.causticMap)
        std::fprintf(stderr, "photons: the plan builds no caustic map for %s; none written\n", o.scene.c_str());

    Device device = Device::open(o.device);
    // The memory plan, before any work: a map that cannot fit under the max allocation (capped
    // or not) fails here with its size and what to change; the batch is the plan's.
    applyBufferCap(device, o.maxBufferMib);
    const MemoryPlan memory = planMemory(photonPassMemoryRequest(geometry, buffers, pass), memoryLimits(device.info()));
    requireMemoryFits(memory);
    pass.batchSize = memory.photonBatch;
    std::fprintf(stderr, "photons %s on %s (%s): global %u, caustic %u photons, seed %llu\n", o.scene.c_str(),
                 device.info().name.c_str(), device.info().platform.c_str(), pass.globalPhotons, pass.causticPhotons,
                 static_cast<unsigned long long>(o.seed));
    PhotonMaps maps;
    if (pass.buildGlobal || pass.buildCaustic) maps = runPhotonPass(device, geometry, buffers, pass);
    std::fputs(maps.stats.summary().c_str(), stderr);

    PhotonPlyMetadata meta;
    meta.scene = o.scene;
    meta.device = device.info().name;
    meta.seed = o.seed;
    meta.globalPhotons = pass.globalPhotons;
    meta.causticPhotons = pass.causticPhotons;
    writePhotonPly(o.output, maps, meta, o.ascii);
    std::fprintf(stderr, "wrote %s: %zu photons (%zu global, %zu caustic), %s\n", o.output.c_str(),
                 maps.global.size() + maps.caustic.size(), maps.global.size(), maps.caustic.size(),
                 o.ascii ? "ASCII" : "binary little-endian");
    return kExitOk;
}

}  // namespace

Run addPhotonsCommand(CLI::App& app) {
    auto o = std::make_shared<PhotonsOptions>();
    CLI::App* sub = app.add_subcommand(
        "photons", "Run the plan's photon pass on a device and write the photon maps as a PLY point cloud");
    sub->add_option("SCENE", o->scene, "Scene file (.json, .gltf, .glb)")->required();
    sub->add_option("-o,--output", o->output, "Output PLY: x y z, power r g b (W), direction dx dy dz, map, bounce")
        ->required();
    sub->add_option("--device", o->device, "OpenCL device: auto|cpu|gpu|<index>|<name substring>")
        ->capture_default_str();
    sub->add_option("--global-photons", o->settings.globalPhotons, "Photons of the global pass when it runs")
        ->check(CLI::Range(1u, 2000000000u))
        ->capture_default_str();
    sub->add_option("--caustic-photons", o->settings.causticPhotons, "Photons of the caustic pass when it runs")
        ->check(CLI::Range(1u, 2000000000u))
        ->capture_default_str();
    sub->add_option("--seed", o->seed, "Random seed: same seed, same PLY bytes")->capture_default_str();
    sub->add_option("--map", o->map, "Maps to write (of those the plan builds)")
        ->check(CLI::IsMember({"global", "caustic", "both"}))
        ->capture_default_str();
    sub->add_flag("--ascii", o->ascii, "ASCII PLY instead of binary little-endian");
    addMaxBufferMibOption(sub, o->maxBufferMib,
                          "Cap every device buffer at this many MiB (smaller batches, same PLY bytes; a map that "
                          "cannot fit fails before work)");
    return [o] { return runPhotons(*o); };
}

}  // namespace pcl::cli
