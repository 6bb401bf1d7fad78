#include <cstdio>
#include <memory>
#include <string>

#include "cli/command.h"
#include "core/error.h"
#include "pipeline/plan.h"
#include "scene/load_scene.h"

namespace pcl::cli {

Run addAnalyzeCommand(CLI::App& app) {
    struct Options {
        std::string scene;
        PlanSettings settings;
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
    return [o] {
        Scene scene = loadScene(o->scene);
        SceneAnalysis a = analyzeScene(scene, o->settings);
        std::fputs(formatPlan(scene, a.paths, a.plan).c_str(), stdout);
        return kExitOk;
    };
}

}  // namespace pcl::cli
