// `photoncl check SCENE [--stage S]`: kernels against their CPU twins (host/check/). The scene is
// prepared once; each stage of check/check_stages.h prints its table and a verdict line.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "check/check_stages.h"
#include "cli/command.h"
#include "cli/memory_option.h"
#include "core/error.h"
#include "device/device.h"
#include "prep/environment_map.h"
#include "prep/media_support.h"
#include "prep/prepared_scene.h"
#include "scene/load_scene.h"

namespace pcl::cli {

Run addCheckCommand(CLI::App& app) {
    struct Options {
        std::string scene, device = "auto", stage = "all";
        CheckOptions check;
        uint64_t maxBufferMib = 0;
    };
    auto o = std::make_shared<Options>();
    CLI::App* sub =
        app.add_subcommand("check", "Run kernel stages and their CPU twins on the same inputs and compare them");
    sub->add_option("SCENE", o->scene, "Scene file (.json, .gltf, .glb)")->required();
    sub->add_option("--device", o->device, "OpenCL device: auto|cpu|gpu|<index>|<name substring>")
        ->capture_default_str();
    std::vector<std::string> names = {"all"};
    std::string help;
    for (const CheckStage& s : checkStages()) {
        names.push_back(s.name);
        help += std::string(s.name) + ": " + s.summary + "; ";
    }
    sub->add_option("--stage", o->stage, help + "all: every one, in this order")
        ->check(CLI::IsMember(names))
        ->capture_default_str();
    sub->add_option("--rays", o->check.rays, "Rays for the trace check")->capture_default_str();
    sub->add_option("--photons", o->check.photons, "Photon paths per pass for the photon checks")
        ->capture_default_str();
    sub->add_option("--seed", o->check.seed, "Seed of the random inputs")->capture_default_str();
    addMaxBufferMibOption(sub, o->maxBufferMib,
                          "Cap every device buffer at this many MiB (the stages split their work)");
    return [o] {
        if (o->device == "ref") throw InputError("check: --device ref has no kernels to check; pick an OpenCL device");
        const Scene scene = loadScene(o->scene);
        refuseEnvironmentInMediaWithoutPathTracer(scene, "check --stage " + o->stage);
        // The photon-pass stages trace media (volume photons), eye_paths and direct_light handle
        // them (transmittance, single scattering, the medium segments), volume_estimate reads the
        // volume maps; the other eye-pass stages (estimates, final gather) keep refusing media.
        // `all` on a scene with media runs these (the BVH traversal too) and names the others.
        const auto handlesMedia = [](const std::string& s) {
            return s == "emit" || s == "trace_photons" || s == "deposit" || s == "pass" || s == "eye_paths" ||
                   s == "direct_light" || s == "volume_estimate";
        };
        if (o->stage != "all" && !handlesMedia(o->stage))
            refuseMediaWithoutPathTracer(scene, "check --stage " + o->stage +
                                                    " (only emit, trace_photons, deposit, pass, eye_paths, "
                                                    "direct_light and volume_estimate handle media)");
        const PreparedScene prepared = prepareScene(scene);
        const bool caustics = prepared.plan.causticMap;
        if (o->stage == "connect_caustics" && !caustics)
            throw InputError(o->scene + ": expected a scene with caustics (a caustic map) for check --stage "
                                        "connect_caustics, got none");
        if (o->stage == "volume_estimate" && !scene.hasMedia())
            throw InputError(o->scene + ": medium: expected a scene with a participating medium for check --stage "
                                        "volume_estimate, got none");
        Device device = Device::open(o->device);
        applyBufferCap(device, o->maxBufferMib);
        std::printf("check %s on %s (%s)\n", o->scene.c_str(), device.info().name.c_str(),
                    device.info().platform.c_str());
        bool ok = true;
        std::string leftOut;
        for (const CheckStage& stage : checkStages()) {
            if (o->stage != "all" && o->stage != stage.name) continue;
            if (o->stage == "all") {
                const std::string name = stage.name;
                if (name == "volume_estimate" && !scene.hasMedia()) continue;  // no volume map to read
                if (name == "connect_caustics" && !caustics) continue;         // no caustic photons
                if (scene.hasMedia() && name != "trace" && !handlesMedia(name)) {
                    leftOut += (leftOut.empty() ? "" : ", ") + name;
                    continue;
                }
            }
            for (const CheckReport& r : stage.run(device, scene, prepared, o->check)) {
                std::printf("stage %s: kernel vs %s\n%s", r.stage.c_str(), stage.against, r.table.c_str());
                std::printf("stage %s: %s\n", r.stage.c_str(), r.passed ? "PASSED" : "FAILED");
                std::fflush(stdout);
                ok = ok && r.passed;
            }
        }
        if (!leftOut.empty())
            std::printf("stages left out (the scene has participating media, which they do not read yet): %s\n",
                        leftOut.c_str());
        return ok ? kExitOk : kExitCheckFailed;
    };
}

}  // namespace pcl::cli
