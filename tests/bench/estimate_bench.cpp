// Irradiance-estimate benchmarks: estimates per second for each filter,
// k = 50 and 100, on 1M photons uniform on the unit square (z = 0, normals +z), through the
// device kd-tree and hash grid (pipeline/estimate: kNN + estimate kernels, the map built once),
// and the CPU twin (reference/estimate: brute-force kNN over the whole map, then the same
// estimate, all cores) on a few queries — the twin is a reference, not a competitor: its
// brute force is O(photons) per query.
//
// Counters: queries_per_s (device: kernel event time of the kNN and estimate launches; twin:
// wall time), queries_per_cpu_s (process CPU time), estimate_share (the estimate kernels'
// part of the device time; the rest is the kNN search). Ratios device / twin per filter and k are
// printed after the runs.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "bench_common.h"
#include "pipeline/estimate.h"
#include "reference/estimate.h"
#include "shared/sampling.h"

namespace pcl {
namespace {

using bench::cpuSeconds;
using bench::device;
using bench::rates;

constexpr size_t kPhotons = 1000000;
constexpr size_t kQueries = 1u << 15;
constexpr size_t kTwinQueries = 256;

const std::vector<PclPhoton>& photons() {
    static const std::vector<PclPhoton> map = [] {
        std::mt19937_64 rng(1);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        std::vector<PclPhoton> m(kPhotons);
        for (auto& p : m) {
            p = PclPhoton{};
            p.x = u(rng), p.y = u(rng), p.z = 0.0f;
            p.rgbe = photon_rgbe_encode(1e-6f, 1e-6f, 1e-6f);
            p.packed = photon_dir_encode(0.0f, 0.0f, 1.0f);
            p.normal = photon_normal_encode(0.0f, 0.0f, 1.0f);
        }
        return m;
    }();
    return map;
}

// r_max: the radius expected to hold 2k photons.
float radiusFor(uint32_t k) { return float(std::sqrt(2.0 * k / (kPhotons * 3.14159265358979))); }

std::vector<PclEstimateQuery> queries(size_t n, uint32_t k) {
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<float> u(0.05f, 0.95f);
    const float r = radiusFor(k);
    std::vector<PclEstimateQuery> qs(n);
    for (auto& q : qs) {
        q = PclEstimateQuery{};
        q.x = u(rng), q.y = u(rng), q.z = 0.0f;
        q.nz = 1.0f;
        q.maxRadius2 = r * r;
        q.k = k;
    }
    return qs;
}

std::string key(const char* who, EstimateFilter f, uint32_t k) {
    return std::string(who) + "/" + estimateFilterName(f) + "/" + std::to_string(k);
}

void BM_DeviceEstimate(benchmark::State& state, KnnStructure s, EstimateFilter f, uint32_t k) {
    Device& dev = device();
    const std::vector<PclEstimateQuery> qs = queries(kQueries, k);
    const PhotonMapOnDevice map(dev, photons(), s, radiusFor(k));
    cl::Buffer qbuf = dev.upload(qs);
    cl::Buffer out = dev.allocate<PclEstimate>(qs.size());
    EstimateSettings settings;
    settings.filter = f;
    estimateBuffers(dev, map, qbuf, 64, k, settings, nullptr, out);  // warm-up: program builds
    double kernel = 0, cpu = 0, estimateOnly = 0;
    size_t done = 0;
    for (auto _ : state) {
        const double c0 = cpuSeconds();
        const EstimateTiming t = estimateBuffers(dev, map, qbuf, qs.size(), k, settings, nullptr, out);
        cpu += cpuSeconds() - c0;
        kernel += t.knnSeconds + t.estimateSeconds;
        estimateOnly += t.estimateSeconds;
        done += qs.size();
        state.SetIterationTime(t.knnSeconds + t.estimateSeconds);
    }
    state.counters["queries_per_s"] = done / kernel;
    state.counters["queries_per_cpu_s"] = done / cpu;
    state.counters["build_s"] = map.buildSeconds();
    state.counters["estimate_share"] = estimateOnly / kernel;  // the rest is the kNN search
    rates()[key(s == KnnStructure::KdTree ? "kdtree" : "grid", f, k)] = done / cpu;
}

void BM_TwinEstimate(benchmark::State& state, EstimateFilter f, uint32_t k) {
    const std::vector<PclEstimateQuery> qs = queries(kTwinQueries, k);
    EstimateSettings settings;
    settings.filter = f;
    double wall = 0, cpu = 0;
    size_t done = 0;
    for (auto _ : state) {
        const double c0 = cpuSeconds();
        const auto w0 = std::chrono::steady_clock::now();
        const std::vector<PclEstimate> e = referenceEstimate(photons(), qs, settings, nullptr);
        benchmark::DoNotOptimize(e.data());
        const double w = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
        wall += w;
        cpu += cpuSeconds() - c0;
        done += qs.size();
        state.SetIterationTime(w);
    }
    state.counters["queries_per_s"] = done / wall;
    state.counters["queries_per_cpu_s"] = done / cpu;
    rates()[key("twin", f, k)] = done / cpu;
}

const uint32_t kKs[] = {50, 100};

void registerAll() {
    for (uint32_t k : kKs)
        for (EstimateFilter f : allEstimateFilters()) {
            const std::string suffix = std::string(estimateFilterName(f)) + "/k" + std::to_string(k);
            benchmark::RegisterBenchmark(("EstimateKdTree/" + suffix).c_str(), BM_DeviceEstimate, KnnStructure::KdTree,
                                         f, k)
                ->Unit(benchmark::kMillisecond)
                ->UseManualTime()
                ->Iterations(2);
            benchmark::RegisterBenchmark(("EstimateHashGrid/" + suffix).c_str(), BM_DeviceEstimate,
                                         KnnStructure::HashGrid, f, k)
                ->Unit(benchmark::kMillisecond)
                ->UseManualTime()
                ->Iterations(2);
            benchmark::RegisterBenchmark(("EstimateTwin/" + suffix).c_str(), BM_TwinEstimate, f, k)
                ->Unit(benchmark::kMillisecond)
                ->UseManualTime()
                ->Iterations(1);
        }
}

}  // namespace
}  // namespace pcl

int main(int argc, char** argv) {
    pcl::bench::runBenchmarks(argc, argv, pcl::registerAll);
    auto& r = pcl::rates();
    for (uint32_t k : pcl::kKs)
        for (pcl::EstimateFilter f : pcl::allEstimateFilters()) {
            auto t = r.find(pcl::key("kdtree", f, k)), g = r.find(pcl::key("grid", f, k)),
                 w = r.find(pcl::key("twin", f, k));
            if (t == r.end() || g == r.end() || w == r.end()) continue;
            std::printf("estimate %s k=%u queries per CPU-second: kd-tree %.0f, grid %.0f, twin (brute force) %.0f; "
                        "device / twin: kd-tree %.1f, grid %.1f\n",
                        pcl::estimateFilterName(f), k, t->second, g->second, w->second, t->second / w->second,
                        g->second / w->second);
        }
    return 0;
}
