// Photon-map build benchmarks, ratios printed after the runs:
//   Sort/Device/<bits>/<n>   the device radix sort (pipeline/sort) of n (key, value) pairs
//                            resident on the device (the input is restored by a buffer copy
//                            outside the timed region); device time from event profiling
//   Sort/StdPar/<bits>/<n>   __gnu_parallel::sort (libstdc++ parallel mode, OpenMP, all cores)
//                            of the same pairs as std::pair<key, value> by key — unstable, so it
//                            does less than the device's stable sort
//   KdTree/Device/<n>        buildKdTree on n photons uniform in a box (device time)
//   KdTree/Twin/<n>          referenceBuildKdTree (one thread) on the same photons
// Timed by wall clock (UseManualTime): both sides use every core. On a machine shared with other
// work, read the ratios from one run only. Counter keys_per_s / photons_per_s.
#include <benchmark/benchmark.h>

#include <parallel/algorithm>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <thread>

#include "bench_common.h"
#include "device/device.h"
#include "pipeline/kdtree.h"
#include "pipeline/sort.h"
#include "reference/kdtree.h"

namespace pcl {
namespace {

using bench::device;
using bench::rates;

template <class K>
std::vector<K> randomKeys(size_t n) {
    std::mt19937_64 rng(n * 7 + sizeof(K));
    std::vector<K> k(n);
    for (K& x : k) x = K(rng());
    return k;
}

template <class K>
void BM_SortDevice(benchmark::State& state) {
    const size_t n = size_t(state.range(0));
    const int bits = int(8 * sizeof(K));
    std::vector<K> keys = randomKeys<K>(n);
    std::vector<uint32_t> values(n);
    for (size_t i = 0; i < n; ++i) values[i] = uint32_t(i);
    Device& dev = device();
    cl::Buffer k0 = dev.upload(keys), v0 = dev.upload(values);
    cl::Buffer k = dev.allocate<K>(n), v = dev.allocate<uint32_t>(n);
    SortWorkspace ws;
    sortPairsOnDevice(dev, k, v, std::min<size_t>(n, 5000), bits, 0, nullptr, &ws);  // programs built before timing
    double total = 0;
    for (auto _ : state) {
        Device::guard("bench", [&] {
            dev.queue().enqueueCopyBuffer(k0, k, 0, 0, n * sizeof(K));
            dev.queue().enqueueCopyBuffer(v0, v, 0, 0, n * sizeof(uint32_t));
        });
        dev.finish();
        auto t0 = std::chrono::steady_clock::now();
        sortPairsOnDevice(dev, k, v, n, bits, 0, nullptr, &ws);
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        state.SetIterationTime(s);
        total += s;
    }
    const double rate = double(n) * state.iterations() / total;
    state.counters["keys_per_s"] = rate;
    rates()["sort/device/" + std::to_string(bits) + "/" + std::to_string(n)] = rate;
}

template <class K>
void BM_SortStdPar(benchmark::State& state) {
    const size_t n = size_t(state.range(0));
    const int bits = int(8 * sizeof(K));
    std::vector<K> keys = randomKeys<K>(n);
    std::vector<std::pair<K, uint32_t>> pairs0(n), pairs;
    for (size_t i = 0; i < n; ++i) pairs0[i] = {keys[i], uint32_t(i)};
    double total = 0;
    for (auto _ : state) {
        pairs = pairs0;
        auto t0 = std::chrono::steady_clock::now();
        __gnu_parallel::sort(pairs.begin(), pairs.end(),
                             [](const std::pair<K, uint32_t>& a, const std::pair<K, uint32_t>& b) {
                                 return a.first < b.first;
                             });
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        state.SetIterationTime(s);
        total += s;
        benchmark::DoNotOptimize(pairs.data());
    }
    const double rate = double(n) * state.iterations() / total;
    state.counters["keys_per_s"] = rate;
    rates()["sort/std/" + std::to_string(bits) + "/" + std::to_string(n)] = rate;
}

std::vector<PclPhoton> randomPhotons(size_t n) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<PclPhoton> p(n);
    for (size_t i = 0; i < n; ++i)
        p[i] = PclPhoton{2.0f * u(rng), u(rng), 0.5f * u(rng), uint32_t(i), uint32_t(i) & 0xFFFFFFu, 0u};
    return p;
}

void BM_KdTreeDevice(benchmark::State& state) {
    const size_t n = size_t(state.range(0));
    std::vector<PclPhoton> photons = randomPhotons(n);
    Device& dev = device();
    cl::Buffer in = dev.upload(photons);
    buildKdTree(dev, in, n);  // programs built before timing
    double total = 0;
    KdTreeTiming timing;
    uint32_t sorted = 0;
    for (auto _ : state) {
        auto t0 = std::chrono::steady_clock::now();
        DeviceKdTree t = buildKdTree(dev, in, n, &timing);
        sorted = t.sortedLevels;
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        state.SetIterationTime(s);
        total += s;
    }
    const double rate = double(n) * state.iterations() / total;
    state.counters["photons_per_s"] = rate;
    state.counters["sort_s"] = timing.sortSeconds / state.iterations();
    state.counters["other_s"] = timing.otherSeconds / state.iterations();
    state.counters["sorted_levels"] = sorted;
    rates()["kdtree/device"] = rate;
}

void BM_KdTreeTwin(benchmark::State& state) {
    const size_t n = size_t(state.range(0));
    std::vector<PclPhoton> photons = randomPhotons(n);
    double total = 0;
    for (auto _ : state) {
        auto t0 = std::chrono::steady_clock::now();
        ReferenceKdTree t = referenceBuildKdTree(photons);
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        state.SetIterationTime(s);
        total += s;
        benchmark::DoNotOptimize(t.photons.data());
    }
    const double rate = double(n) * state.iterations() / total;
    state.counters["photons_per_s"] = rate;
    rates()["kdtree/twin"] = rate;
}

void registerAll() {
    for (int64_t n : {int64_t(1) << 20, int64_t(10000000)}) {
        const std::string s = std::to_string(n);
        benchmark::RegisterBenchmark(("Sort/Device/32/" + s).c_str(), BM_SortDevice<uint32_t>)
            ->Arg(n)
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond)
            ->Iterations(3);
        benchmark::RegisterBenchmark(("Sort/StdPar/32/" + s).c_str(), BM_SortStdPar<uint32_t>)
            ->Arg(n)
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond)
            ->Iterations(3);
        benchmark::RegisterBenchmark(("Sort/Device/64/" + s).c_str(), BM_SortDevice<uint64_t>)
            ->Arg(n)
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond)
            ->Iterations(3);
        benchmark::RegisterBenchmark(("Sort/StdPar/64/" + s).c_str(), BM_SortStdPar<uint64_t>)
            ->Arg(n)
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond)
            ->Iterations(3);
    }
    benchmark::RegisterBenchmark("KdTree/Device/1M", BM_KdTreeDevice)
        ->Arg(1 << 20)
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond)
        ->Iterations(2);
    benchmark::RegisterBenchmark("KdTree/Twin/1M", BM_KdTreeTwin)
        ->Arg(1 << 20)
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond)
        ->Iterations(2);
}

}  // namespace
}  // namespace pcl

int main(int argc, char** argv) {
    pcl::bench::runBenchmarks(argc, argv, pcl::registerAll);
    auto& r = pcl::rates();
    std::printf("std side: __gnu_parallel::sort (OpenMP, %u hardware threads) of (key, value) pairs by key\n",
                std::thread::hardware_concurrency());
    for (int bits : {32, 64})
        for (long n : {1L << 20, 10000000L}) {
            const std::string k = std::to_string(bits) + "/" + std::to_string(n);
            auto d = r.find("sort/device/" + k), s = r.find("sort/std/" + k);
            if (d != r.end() && s != r.end())
                std::printf("sort keys/s, device / std parallel, %d-bit, n = %ld: %.3f (%.3g vs %.3g)\n", bits, n,
                            d->second / s->second, d->second, s->second);
        }
    auto d = r.find("kdtree/device"), t = r.find("kdtree/twin");
    if (d != r.end() && t != r.end())
        std::printf("kd-tree build photons/s, device / twin (one thread), 1M photons: %.3f (%.3g vs %.3g)\n",
                    d->second / t->second, d->second, t->second);
    return 0;
}
