// Eye pass benchmarks: one pass of every eye-pass stage on the device (camera → eye paths →
// direct light → final gather → caustics, and the direct-visualisation preview) on a shipped
// scene at 256 × 256, one sample per pixel, with the device seconds of each stage as counters,
// and the CPU twin of the eye paths and direct light on the same inputs for the ratio.
//
//   eye_pass_bench --benchmark_filter=Device
//   counters: camera_s, eye_s, direct_s, gather_trace_s, gather_irradiance_s, gather_resolve_s,
//             caustics_s, preview_s (device seconds per pass), samples_per_s (whole pass, wall)
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>

#include "bench_common.h"
#include "check/on_device.h"
#include "geometry/scene_geometry.h"
#include "pipeline/camera_rays.h"
#include "pipeline/direct_light.h"
#include "pipeline/eye_estimate.h"
#include "pipeline/eye_paths.h"
#include "pipeline/final_gather.h"
#include "pipeline/photon_pass.h"
#include "pipeline/precomputed_irradiance.h"
#include "prep/projection_map.h"
#include "prep/scene_buffers.h"
#include "reference/direct_light.h"
#include "reference/eye_paths.h"
#include "scene/load_scene.h"

namespace pcl {
namespace {

using bench::device;

constexpr int kSize = 256;
constexpr uint32_t kGatherRays = 16, kLightSamples = 1, kK = 50;

struct Setup {
    Scene scene;
    SceneGeometry geometry;
    SceneBuffers buffers;
    PhotonMaps maps;
    float rMax = 0.0f;
    std::unique_ptr<DeviceScene> deviceScene;
    std::unique_ptr<DeviceAreaLights> lights;
    AreaLightTable table;
    std::unique_ptr<PhotonMapOnDevice> global, caustic;
    DeviceIrradianceMap precomputed;
    double precomputeSeconds = 0.0;
};

const Setup& setup(const std::string& name) {
    static std::map<std::string, std::unique_ptr<Setup>> cache;
    auto& s = cache[name];
    if (!s) {
        s = std::make_unique<Setup>();
        s->scene = loadScene((std::filesystem::path(PHOTONCL_SOURCE_DIR) / "scenes" / (name + ".json")).string());
        s->scene.camera.width = s->scene.camera.height = kSize;
        s->geometry = SceneGeometry::build(s->scene);
        s->buffers = buildSceneBuffers(s->scene, s->geometry);
        buildProjectionMaps(s->scene, s->geometry, s->buffers);
        PhotonPassOptions po;
        po.globalPhotons = 200000;
        po.causticPhotons = 100000;
        s->maps = runPhotonPass(device(), s->geometry, s->buffers, po);
        const Vec3 e = s->geometry.bounds().extent();
        s->rMax = 0.05f * std::sqrt(dot(e, e));
        s->deviceScene = std::make_unique<DeviceScene>(device(), s->geometry, s->buffers);
        s->table = buildAreaLightTable(s->buffers, s->geometry.primitiveCount());
        s->lights = std::make_unique<DeviceAreaLights>(device(), s->table);
        s->global = std::make_unique<PhotonMapOnDevice>(device(), s->maps.global, KnnStructure::KdTree, s->rMax);
        PrecomputedIrradianceOptions pio;
        pio.maxRadius = s->rMax;
        pio.estimate.rayEpsilon = s->buffers.rayEpsilon;
        auto t0 = std::chrono::steady_clock::now();
        s->precomputed = precomputeIrradiance(device(), s->maps.global, pio, s->deviceScene.get());
        s->precomputeSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (!s->maps.caustic.empty())
            s->caustic = std::make_unique<PhotonMapOnDevice>(device(), s->maps.caustic, KnnStructure::KdTree, s->rMax);
    }
    return *s;
}

double seconds(cl::Event e) {
    device().finish();
    return e() ? Device::elapsedSeconds(e) : 0.0;
}

void BM_Device(benchmark::State& state, std::string name) {
    const Setup& s = setup(name);
    Device& dev = device();
    const PclCameraParams cp = cameraParams(s.scene.camera, true, true, eyePassSeed(1, 0), 1);
    const size_t n = cp.sampleCount;
    cl::Buffer rays = dev.allocate<PclRay>(n, CL_MEM_READ_WRITE, "bench: rays");
    cl::Buffer hits = dev.allocate<PclEyeHit>(n, CL_MEM_READ_WRITE, "bench: hits");
    cl::Buffer direct = dev.allocate<PclRadiance>(n, CL_MEM_READ_WRITE, "bench: direct");
    cl::Buffer gather = dev.allocate<PclRadiance>(n, CL_MEM_READ_WRITE, "bench: gather");
    cl::Buffer caustics = dev.allocate<PclRadiance>(n, CL_MEM_READ_WRITE, "bench: caustics");
    cl::Buffer preview = dev.allocate<PclRadiance>(n, CL_MEM_READ_WRITE, "bench: preview");
    const PclEyeParams ep = eyeParams(cp, s.geometry, s.buffers, s.table);
    const PclDirectParams dp = directParams(ep, s.geometry, s.buffers, s.table, kLightSamples, kGatherRays);
    const PclGatherParams gp = gatherParams(dp, kGatherRays, kK, s.rMax * s.rMax);
    PclEyeEstimateParams pe{};
    pe.sampleCount = uint32_t(n);
    pe.k = kK;
    pe.maxRadius2 = s.rMax * s.rMax;
    pe.irradianceStride = 8;
    EstimateSettings es;
    es.rayEpsilon = s.buffers.rayEpsilon;
    auto globalSource = estimateIrradianceSource(*s.global, kK, es, s.deviceScene.get());
    auto causticSource = s.caustic ? estimateIrradianceSource(*s.caustic, kK, es, s.deviceScene.get()) : nullptr;
    auto preSource = precomputedIrradianceSource(s.precomputed);
    PclGatherParams ip = gp;
    ip.histogramCells = 8;
    double cam = 0, eye = 0, dir = 0, gt = 0, gi = 0, gr = 0, ca = 0, pr = 0, wall = 0, gp2 = 0, hi = 0, it2 = 0;
    for (auto _ : state) {
        auto t0 = std::chrono::steady_clock::now();
        cam += seconds(generateCameraRays(dev, cp, rays));
        eye += seconds(traceEyePaths(dev, *s.deviceScene, *s.lights, ep, rays, hits));
        dir += seconds(directLight(dev, *s.deviceScene, *s.lights, dp, hits, direct));
        const GatherTiming g = finalGather(dev, *s.deviceScene, *s.lights, gp, hits, *globalSource, gather);
        gt += g.traceSeconds;
        gi += g.irradianceSeconds;
        gr += g.resolveSeconds;
        if (causticSource) ca += estimateAtEyeHits(dev, pe, hits, s.deviceScene->primInfo, *causticSource, caustics);
        wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        pr += estimateAtEyeHits(dev, pe, hits, s.deviceScene->primInfo, *globalSource, preview);
        const GatherTiming g2 = finalGather(dev, *s.deviceScene, *s.lights, gp, hits, *preSource, gather);
        gp2 += g2.irradianceSeconds;
        auto t1 = std::chrono::steady_clock::now();
        const cl::Buffer hist = buildGatherHistograms(dev, *s.global, ip, hits);
        hi += std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
        it2 += finalGather(dev, *s.deviceScene, *s.lights, ip, hits, hist, *preSource, gather).traceSeconds;
    }
    const double it = double(state.iterations());
    state.counters["camera_s"] = cam / it;
    state.counters["eye_s"] = eye / it;
    state.counters["direct_s"] = dir / it;
    state.counters["gather_trace_s"] = gt / it;
    state.counters["gather_irradiance_s"] = gi / it;
    state.counters["gather_resolve_s"] = gr / it;
    state.counters["caustics_s"] = ca / it;
    state.counters["preview_s"] = pr / it;
    state.counters["pass_wall_s"] = wall / it;
    state.counters["gather_precomputed_s"] = gp2 / it;
    state.counters["histograms_wall_s"] = hi / it;
    state.counters["samples_per_s"] = double(n) * it / wall;
    std::printf("[figure] importance histograms (G = 8, k = %u): %.4f s wall per pass; importance-sampled gather trace "
                "%.4f s vs %.4f s cosine\n",
                kK, hi / it, it2 / it, gt / it);
    std::printf("[figure] gather irradiance by precomputed lookup (%zu points, built in %.2f s wall): %.4f s per pass "
                "vs %.4f s for the full estimate (%.1fx)\n",
                s.precomputed.count, s.precomputeSeconds, gp2 / it, gi / it, gi / std::max(gp2, 1e-12));
    std::printf("[figure] eye pass %s %dx%d, 1 spp, M=%u, N=%u, k=%u, %zu global / %zu caustic photons: camera %.4f s, "
                "eye paths %.4f s, direct %.4f s, gather trace %.4f s + irradiance %.4f s + resolve %.4f s, caustics "
                "%.4f s, preview %.4f s (device seconds per pass); pass wall %.3f s\n",
                name.c_str(), kSize, kSize, kLightSamples, kGatherRays, kK, s.maps.global.size(), s.maps.caustic.size(),
                cam / it, eye / it, dir / it, gt / it, gi / it, gr / it, ca / it, pr / it, wall / it);
}

// The twin of the two ray-tracing stages without photon maps, on the device's own inputs.
void BM_Twin(benchmark::State& state, std::string name) {
    const Setup& s = setup(name);
    Device& dev = device();
    const PclCameraParams cp = cameraParams(s.scene.camera, true, true, eyePassSeed(1, 0), 1);
    const std::vector<PclRay> rays = cameraRaysOnDevice(dev, cp);
    const PclEyeParams ep = eyeParams(cp, s.geometry, s.buffers, s.table);
    const PclDirectParams dp = directParams(ep, s.geometry, s.buffers, s.table, kLightSamples, kGatherRays);
    double eye = 0, dir = 0;
    for (auto _ : state) {
        auto t0 = std::chrono::steady_clock::now();
        const std::vector<PclEyeHit> hits = referenceEyePaths(s.geometry, s.buffers, rays, ep);
        auto t1 = std::chrono::steady_clock::now();
        benchmark::DoNotOptimize(referenceDirectLight(s.geometry, s.buffers, hits, dp));
        auto t2 = std::chrono::steady_clock::now();
        eye += std::chrono::duration<double>(t1 - t0).count();
        dir += std::chrono::duration<double>(t2 - t1).count();
    }
    const double it = double(state.iterations());
    state.counters["eye_s"] = eye / it;
    state.counters["direct_s"] = dir / it;
    std::printf("[figure] twin %s %dx%d: eye paths %.4f s, direct %.4f s (wall, all threads)\n", name.c_str(), kSize,
                kSize, eye / it, dir / it);
}

void registerAll() {
    for (const char* name : {"cornell-spheres"}) {
        benchmark::RegisterBenchmark((std::string("Device/") + name).c_str(), BM_Device, std::string(name))
            ->Iterations(2)
            ->Unit(benchmark::kSecond);
        benchmark::RegisterBenchmark((std::string("Twin/") + name).c_str(), BM_Twin, std::string(name))
            ->Iterations(1)
            ->Unit(benchmark::kSecond);
    }
}

}  // namespace
}  // namespace pcl

int main(int argc, char** argv) {
    pcl::bench::runBenchmarks(argc, argv, pcl::registerAll);
    return 0;
}
