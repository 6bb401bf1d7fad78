// `photoncl check --stage NAME`: every kernel stage against its CPU twin on the same inputs.
// One list of stages, each with its own file under host/check/: trace.cpp, emit.cpp,
// trace_photons.cpp, deposit.cpp, pass.cpp (their report: photon_stages.h), sort.cpp, build.cpp
// (maps.h), knn.cpp, estimate.cpp (with precomputed_irradiance.cpp, the estimate stage's second
// part), eye_stages.cpp (eye_paths, direct_light, connect_caustics), volume_estimate.cpp, render.cpp. Each file's typed report keeps the stage's own figures (tests read those);
// the command gets them as CheckReport. It prepares the scene once and runs the stages it was
// asked for in this order.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "prep/prepared_scene.h"
#include "scene/scene.h"

namespace pcl {

// What the command line sets for every stage.
struct CheckOptions {
    size_t rays = 100000;      // trace: random rays
    uint32_t photons = 50000;  // photon paths per pass of the photon and map stages
    uint64_t seed = 1;         // of every random input
};

// The one result type every stage gives the command: printable, with a verdict.
struct CheckReport {
    std::string stage;  // the --stage name, or a part of it ("estimate (precomputed irradiance)")
    std::string table;  // the stage's table: one line per comparison, then its tolerances
    bool passed = false;
};

struct CheckStage {
    const char* name;     // --stage NAME
    const char* summary;  // what is compared with what (for --help)
    const char* against;  // what the kernel is compared with, for the report's title
    std::vector<CheckReport> (*run)(Device& device, const Scene& scene, const PreparedScene& prepared,
                                    const CheckOptions& options);
};

// Every stage, in the order `--stage all` runs them.
const std::vector<CheckStage>& checkStages();

}  // namespace pcl
