// Photon pass benchmarks: photon paths per second of the device pass (pipeline/photon_pass:
// emit → trace → deposit, PoCL on all cores or whatever device `auto` opens) and of the CPU
// twin (reference/photon_pass on all threads) on the same scene, settings and seed. Timed by
// the CPU time of the whole process (PoCL's workers and the twin's threads included), so
// paths_per_s is paths per CPU-second and the device/twin ratio holds on a machine shared with
// other work; the ratio is printed per scene after the runs. On a GPU the CPU time is the
// host's waiting, so there read the wall-clock counter paths_per_wall_s instead.
//
//   photon_pass_bench --benchmark_filter=Device     the device pass only
//   counters: paths_per_s, paths_per_wall_s, records, rays_per_path (BVH rays a path traced, on
//   average: scripts/bench_table.py sets paths/s against the traversal kernel's rays/s over it),
//   emit_s / trace_s / deposit_s (device time per run)
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>
#include <memory>

#include "bench_common.h"
#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "pipeline/photon_pass.h"
#include "prep/projection_map.h"
#include "prep/scene_buffers.h"
#include "reference/photon_pass.h"
#include "scene/load_scene.h"

namespace pcl {
namespace {

using bench::cpuSeconds;
using bench::device;
using bench::rates;

constexpr uint32_t kGlobal = 1u << 18, kCaustic = 1u << 16, kMaxDepth = 64;
constexpr uint64_t kSeed = 1;

struct Loaded {
    Scene scene;
    SceneGeometry geometry;
    SceneBuffers buffers;
};

const Loaded& loaded(const std::string& name) {
    static std::map<std::string, std::unique_ptr<Loaded>> cache;
    auto& l = cache[name];
    if (!l) {
        auto path = std::filesystem::path(PHOTONCL_SOURCE_DIR) / "scenes" / (name + ".json");
        Scene s = loadScene(path.string());
        SceneGeometry g = SceneGeometry::build(s);
        SceneBuffers b = buildSceneBuffers(s, g);
        buildProjectionMaps(s, g, b);
        l = std::make_unique<Loaded>(Loaded{std::move(s), std::move(g), std::move(b)});
    }
    return *l;
}

void BM_Device(benchmark::State& state, std::string name) {
    const Loaded& l = loaded(name);
    PhotonPassOptions o;
    o.globalPhotons = kGlobal;
    o.causticPhotons = kCaustic;
    o.maxDepth = kMaxDepth;
    o.seed = kSeed;
    runPhotonPass(device(), l.geometry, l.buffers, o);  // programs built and cached before timing
    double cpu = 0, wall = 0, emitS = 0, traceS = 0, depositS = 0;
    size_t paths = 0, records = 0, rays = 0;
    for (auto _ : state) {
        double c0 = cpuSeconds();
        auto w0 = std::chrono::steady_clock::now();
        PhotonMaps maps = runPhotonPass(device(), l.geometry, l.buffers, o);
        wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
        cpu += cpuSeconds() - c0;
        paths += maps.stats.global.emitted + maps.stats.caustic.emitted;
        rays += maps.stats.global.bounces + maps.stats.caustic.bounces;  // a path ending at bounce b traced b rays
        records = maps.global.size() + maps.caustic.size();
        emitS = maps.stats.emitSeconds;
        traceS = maps.stats.traceSeconds;
        depositS = maps.stats.depositSeconds;
    }
    state.counters["paths_per_s"] = paths / cpu;
    state.counters["paths_per_wall_s"] = paths / wall;
    state.counters["records"] = double(records);
    state.counters["rays_per_path"] = paths ? double(rays) / double(paths) : 0.0;
    state.counters["emit_s"] = emitS;
    state.counters["trace_s"] = traceS;
    state.counters["deposit_s"] = depositS;
    rates()["device/" + name] = paths / cpu;
}

void BM_Twin(benchmark::State& state, std::string name) {
    const Loaded& l = loaded(name);
    ReferencePhotonPassSettings s;
    s.globalPhotons = kGlobal;
    s.causticPhotons = kCaustic;
    s.maxDepth = kMaxDepth;
    s.seed = kSeed;
    double cpu = 0, wall = 0;
    size_t paths = 0, records = 0;
    for (auto _ : state) {
        double c0 = cpuSeconds();
        auto w0 = std::chrono::steady_clock::now();
        ReferencePhotonMaps maps = runPhotonPassReference(l.buffers, l.geometry, s);
        wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
        cpu += cpuSeconds() - c0;
        paths += maps.globalStats.paths + maps.causticStats.paths;
        records = maps.global.size() + maps.caustic.size();
    }
    state.counters["paths_per_s"] = paths / cpu;
    state.counters["paths_per_wall_s"] = paths / wall;
    state.counters["records"] = double(records);
    rates()["twin/" + name] = paths / cpu;
}

const char* kScenes[] = {"cornell-box", "cornell-spheres", "motion-dof"};

void registerAll() {
    for (const char* n : kScenes) {
        benchmark::RegisterBenchmark((std::string("Device/") + n).c_str(), BM_Device, std::string(n))
            ->Unit(benchmark::kMillisecond)
            ->MeasureProcessCPUTime()
            ->Iterations(3);
        benchmark::RegisterBenchmark((std::string("Twin/") + n).c_str(), BM_Twin, std::string(n))
            ->Unit(benchmark::kMillisecond)
            ->MeasureProcessCPUTime()
            ->Iterations(3);
    }
}

}  // namespace
}  // namespace pcl

int main(int argc, char** argv) {
    pcl::bench::runBenchmarks(argc, argv, pcl::registerAll);
    auto& r = pcl::rates();
    for (const char* n : pcl::kScenes) {
        auto d = r.find(std::string("device/") + n), t = r.find(std::string("twin/") + n);
        if (d != r.end() && t != r.end())
            std::printf("photon paths per CPU-second, device / twin, %s: %.3f (%.0f vs %.0f)\n", n,
                        d->second / t->second, d->second, t->second);
    }
    return 0;
}
