// Precomputed irradiance benchmarks: per-query cost of a lookup
// (pipeline/precomputed_irradiance: one nearest-neighbour search with the normal test) against
// the full estimate it replaces (pipeline/estimate: k-nearest-neighbour search + estimate), for
// k = 50 and 100 on 1M photons, on the device; and the one-off precomputation per photon map.
//
// Map: 1M photons uniform on the six inner faces of the unit cube, each with its face's inward
// normal and an incoming direction along it (a photon map's 2-D density, with faces meeting at
// edges where the normal test matters). Queries: 2^16 points drawn the same way, with their
// face's normal. r_max per k is the radius expected to hold 2k photons on a face. Every 4th
// photon is stored (250 000 points).
//
// Counters: queries_per_s from the kernels' event times (estimate: kNN + estimate kernels;
// lookup: the lookup kernel), queries_per_cpu_s from process CPU time (the fair figure on a
// shared CPU; meaningless on a GPU). After the runs, one line per k: the lookup's speed-up over
// the full estimate (ratios of queries per second, device time and CPU time).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#ifdef PHOTONCL_HAVE_NANOFLANN
#include <nanoflann.hpp>
#endif

#include "bench_common.h"
#include "pipeline/estimate.h"
#include "pipeline/precomputed_irradiance.h"
#include "pipeline/query_order.h"
#include "reference/trace_photons.h"

namespace pcl {
namespace {

using bench::cpuSeconds;
using bench::device;
using bench::rates;

constexpr size_t kPhotons = 1000000;
constexpr size_t kQueries = 1u << 16;
constexpr double kPi = 3.14159265358979323846;
const uint32_t kKs[] = {50, 100};

// A point uniform on the six faces of the unit cube and the face's inward normal.
void onWalls(std::mt19937_64& rng, float p[3], float n[3]) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::uniform_int_distribution<int> face(0, 5);
    const int f = face(rng);
    p[0] = u(rng), p[1] = u(rng), p[2] = u(rng);
    p[f / 2] = float(f % 2);
    n[0] = n[1] = n[2] = 0.0f;
    n[f / 2] = f % 2 ? -1.0f : 1.0f;
}

struct Data {
    std::vector<PclPhoton> photons;
    std::vector<PclEstimateQuery> queries;  // k and maxRadius2 set per benchmark
};

const Data& data() {
    static Data d = [] {
        Data d;
        std::mt19937_64 rng(5);
        d.photons.resize(kPhotons);
        for (PclPhoton& ph : d.photons) {
            float p[3], n[3];
            onWalls(rng, p, n);
            ph = PclPhoton{};
            ph.x = p[0], ph.y = p[1], ph.z = p[2];
            ph.rgbe = referenceEncodeRgbe(Vec3(1e-6f));
            ph.packed = referenceEncodeDirection(Vec3(n[0], n[1], n[2]));
            ph.normal = referenceEncodeNormal(Vec3(n[0], n[1], n[2]));
        }
        d.queries.resize(kQueries);
        for (PclEstimateQuery& q : d.queries) {
            float p[3], n[3];
            onWalls(rng, p, n);
            q = PclEstimateQuery{};
            q.x = p[0], q.y = p[1], q.z = p[2];
            q.nx = n[0], q.ny = n[1], q.nz = n[2];
        }
        return d;
    }();
    return d;
}

// The radius expected to hold 2k photons: density n / 6 per unit area.
float radiusFor(uint32_t k) { return float(std::sqrt(2.0 * k / (kPhotons / 6.0 * kPi))); }

std::vector<PclEstimateQuery> queries(uint32_t k) {
    std::vector<PclEstimateQuery> qs = data().queries;
    const float r = radiusFor(k);
    for (PclEstimateQuery& q : qs) q.maxRadius2 = r * r, q.k = k;
    return qs;
}

// The structures, built once per k and kept for the lookups.
struct Built {
    std::unique_ptr<PhotonMapOnDevice> global;
    DeviceIrradianceMap irradiance;
    double precomputeWall = 0.0;
};
Built& built(uint32_t k) {
    static std::map<uint32_t, Built> cache;
    Built& b = cache[k];
    if (!b.global) {
        Device& dev = device();
        b.global = std::make_unique<PhotonMapOnDevice>(dev, data().photons, KnnStructure::KdTree, radiusFor(k));
        PrecomputedIrradianceOptions o;
        o.k = k;
        o.maxRadius = radiusFor(k);
        const auto t0 = std::chrono::steady_clock::now();
        b.irradiance = precomputeIrradiance(dev, b.global->photons(), kPhotons, o, nullptr);
        b.precomputeWall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    return b;
}

void BM_FullEstimate(benchmark::State& state, uint32_t k) {
    Device& dev = device();
    const Built& b = built(k);
    const std::vector<PclEstimateQuery> qs = queries(k);
    cl::Buffer qbuf = dev.upload(qs);
    cl::Buffer results = dev.allocate<PclEstimate>(qs.size());
    const EstimateSettings settings;
    estimateBuffers(dev, *b.global, qbuf, 64, k, settings, nullptr, results);  // warm-up: program builds
    double kernel = 0, cpu = 0;
    size_t done = 0;
    for (auto _ : state) {
        const double c0 = cpuSeconds();
        const EstimateTiming t = estimateBuffers(dev, *b.global, qbuf, qs.size(), k, settings, nullptr, results);
        cpu += cpuSeconds() - c0;
        kernel += t.knnSeconds + t.estimateSeconds;
        done += qs.size();
        state.SetIterationTime(t.knnSeconds + t.estimateSeconds);
    }
    state.counters["queries_per_s"] = done / kernel;
    state.counters["queries_per_cpu_s"] = done / cpu;
    rates()["estimate/" + std::to_string(k)] = done / kernel;
    rates()["estimate-cpu/" + std::to_string(k)] = done / cpu;
}

void BM_Lookup(benchmark::State& state, uint32_t k) {
    Device& dev = device();
    const Built& b = built(k);
    const std::vector<PclEstimateQuery> qs = queries(k);
    cl::Buffer qbuf = dev.upload(qs);
    DeviceIrradianceLookup out;
    lookupIrradiance(dev, b.irradiance, qbuf, 64, out);  // warm-up
    double kernel = 0, cpu = 0;
    size_t done = 0;
    for (auto _ : state) {
        const double c0 = cpuSeconds();
        const double t = lookupIrradiance(dev, b.irradiance, qbuf, qs.size(), out);
        cpu += cpuSeconds() - c0;
        kernel += t;
        done += qs.size();
        state.SetIterationTime(t);
    }
    const std::vector<uint32_t> chosen = dev.download<uint32_t>(out.chosen, qs.size());
    size_t empty = 0;
    for (uint32_t c : chosen) empty += c == PCL_NO_HIT;
    state.counters["queries_per_s"] = done / kernel;
    state.counters["queries_per_cpu_s"] = done / cpu;
    state.counters["empty"] = double(empty);
    state.counters["points"] = double(b.irradiance.count);
    rates()["lookup/" + std::to_string(k)] = done / kernel;
    rates()["lookup-cpu/" + std::to_string(k)] = done / cpu;
}

// As render's final gather reads it: the queries put in Morton order first (pipeline/query_order),
// the lookup, the results scattered back; wall time of the three (the sort included).
void BM_LookupOrdered(benchmark::State& state, uint32_t k) {
    Device& dev = device();
    const Built& b = built(k);
    const std::vector<PclEstimateQuery> qs = queries(k);
    cl::Buffer qbuf = dev.upload(qs);
    cl::Buffer results = dev.allocate<cl_float4>(qs.size(), CL_MEM_READ_WRITE, "bench: lookups");
    DeviceIrradianceLookup out;
    auto once = [&] {
        const QueryOrder order = orderQueries(dev, qbuf, qs.size(), radiusFor(k) / 4.0f);
        lookupIrradiance(dev, b.irradiance, order.sorted, qs.size(), out);
        scatterResults(dev, order, out.irradiance, 4, results);
        dev.finish();
    };
    once();  // warm-up: program builds
    double wall = 0;
    size_t done = 0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        once();
        const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        wall += t;
        done += qs.size();
        state.SetIterationTime(t);
    }
    state.counters["queries_per_s"] = done / wall;
}

#ifdef PHOTONCL_HAVE_NANOFLANN
// The peer of the lookup: nanoflann's k = 1 search over the same points on all cores (no cover
// or normal test, so less work than the lookup does).
struct PointCloud {
    std::vector<float> xyz;
    size_t kdtree_get_point_count() const { return xyz.size() / 3; }
    float kdtree_get_pt(size_t i, size_t dim) const { return xyz[3 * i + dim]; }
    template <class B>
    bool kdtree_get_bbox(B&) const {
        return false;
    }
};
using NearestTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, PointCloud>, PointCloud, 3, uint32_t>;

void BM_NanoflannNearest(benchmark::State& state, uint32_t k) {
    Device& dev = device();
    const Built& b = built(k);
    PointCloud cloud;
    for (const PclIrradiancePoint& p : downloadIrradiancePoints(dev, b.irradiance))
        cloud.xyz.insert(cloud.xyz.end(), {p.x, p.y, p.z});
    NearestTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    const std::vector<PclEstimateQuery> qs = queries(k);
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    std::vector<uint32_t> nearest(qs.size());
    double wall = 0;
    size_t done = 0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<std::thread> pool;
        for (unsigned t = 0; t < threads; ++t)
            pool.emplace_back([&, t] {
                for (size_t q = t * qs.size() / threads; q < (t + 1) * qs.size() / threads; ++q) {
                    const float at[3] = {qs[q].x, qs[q].y, qs[q].z};
                    float d2 = 0.0f;
                    tree.knnSearch(at, 1, &nearest[q], &d2);
                }
            });
        for (std::thread& th : pool) th.join();
        const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        wall += t;
        done += qs.size();
        state.SetIterationTime(t);
    }
    state.counters["queries_per_s"] = done / wall;
    state.counters["threads"] = threads;
}
#endif

// The one-off cost per photon map: selection, the others' kd-tree, the estimates, the lookup tree.
void BM_Precompute(benchmark::State& state, uint32_t k) {
    Device& dev = device();
    const Built& b = built(k);  // warm-up: program builds
    PrecomputedIrradianceOptions o;
    o.k = k;
    o.maxRadius = radiusFor(k);
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        const DeviceIrradianceMap m = precomputeIrradiance(dev, b.global->photons(), kPhotons, o, nullptr);
        state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        state.counters["estimate_s"] = m.timing.estimate.knnSeconds + m.timing.estimate.estimateSeconds;
        state.counters["knn_s"] = m.timing.estimate.knnSeconds;  // of estimate_s: the search, the rest the filter sums
        state.counters["others_map_s"] = m.timing.mapSeconds;
        state.counters["tree_s"] = m.timing.treeSeconds;
    }
    state.counters["points"] = double(b.irradiance.count);
}

void registerAll() {
    for (uint32_t k : kKs) {
        const std::string suffix = "/walls1M/k" + std::to_string(k);
        benchmark::RegisterBenchmark(("FullEstimate" + suffix).c_str(), BM_FullEstimate, k)
            ->Unit(benchmark::kMillisecond)
            ->UseManualTime()
            ->Iterations(2);
        benchmark::RegisterBenchmark(("IrradianceLookup" + suffix).c_str(), BM_Lookup, k)
            ->Unit(benchmark::kMillisecond)
            ->UseManualTime()
            ->Iterations(5);
        benchmark::RegisterBenchmark(("IrradianceLookupOrdered" + suffix).c_str(), BM_LookupOrdered, k)
            ->Unit(benchmark::kMillisecond)
            ->UseManualTime()
            ->Iterations(5);
#ifdef PHOTONCL_HAVE_NANOFLANN
        benchmark::RegisterBenchmark(("NanoflannNearest" + suffix).c_str(), BM_NanoflannNearest, k)
            ->Unit(benchmark::kMillisecond)
            ->UseManualTime()
            ->Iterations(5);
#endif
        benchmark::RegisterBenchmark(("IrradiancePrecompute" + suffix).c_str(), BM_Precompute, k)
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
    for (uint32_t k : pcl::kKs) {
        const std::string key = std::to_string(k);
        auto e = r.find("estimate/" + key), l = r.find("lookup/" + key);
        auto ec = r.find("estimate-cpu/" + key), lc = r.find("lookup-cpu/" + key);
        if (e == r.end() || l == r.end() || ec == r.end() || lc == r.end()) continue;
        std::printf("[figure] precomputed irradiance k=%u, 1M photons on %s: full estimate %.0f queries/s, lookup %.0f "
                    "queries/s: lookup %.1fx faster (device time), %.1fx per CPU-second\n",
                    k, pcl::bench::device().info().name.c_str(), e->second, l->second, l->second / e->second,
                    lc->second / ec->second);
    }
    return 0;
}
