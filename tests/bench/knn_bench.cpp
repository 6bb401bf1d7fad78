// k-nearest-neighbour benchmarks: queries per second for k = 50, 100, 500 on
// 1M photons, the device search through the kd-tree and through the hash grid (pipeline/knn),
// against nanoflann's KD-tree on all cores (std::thread over the queries); and build times of
// the device kd-tree, the device hash grid and nanoflann's tree.
//
// Maps: "box", 1M photons uniform in the unit cube; "walls", 1M photons uniform on the six faces
// of the unit cube (a photon map's 2-D density). Queries: 2^16 points drawn like the photons
// (on the walls for "walls"). r_max per k is the radius expected to hold 2k photons, so almost
// every query finds its k; the grid's cells are 2 r_max. nanoflann runs its plain knnSearch
// (no radius limit: the same neighbours whenever k fit inside r_max) and, as NanoflannRmax, a
// search bounded by r_max from the start like the device's; ratios use the faster of the two.
//
// Ordered variants (".../ordered"): the same queries in render's order (pipeline/query_order,
// Morton code of cells of r_max / 4), the device's time including that sort on the device each
// run, nanoflann's on the same order.
//
// Counters: queries_per_s (device: kernel event time; nanoflann: wall time over all threads),
// queries_per_cpu_s (process CPU time: PoCL's workers and nanoflann's threads alike — the fair
// figure on a shared CPU; meaningless for a GPU, read queries_per_s there). The ratios
// device/nanoflann are printed per map and k after the runs.
#include <benchmark/benchmark.h>

#include <nanoflann.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "bench_common.h"
#include "device/device.h"
#include "pipeline/hashgrid.h"
#include "pipeline/kdtree.h"
#include "pipeline/knn.h"
#include "pipeline/query_order.h"

namespace pcl {
namespace {

using bench::cpuSeconds;
using bench::device;
using bench::rates;

constexpr size_t kPhotons = 1000000;
constexpr size_t kQueries = 1u << 16;
constexpr double kPi = 3.14159265358979323846;

// A point uniform on the six faces of the unit cube.
void onWalls(std::mt19937_64& rng, float p[3]) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::uniform_int_distribution<int> face(0, 5);
    const int f = face(rng);
    p[0] = u(rng), p[1] = u(rng), p[2] = u(rng);
    p[f / 2] = float(f % 2);
}

struct Data {
    std::vector<PclPhoton> photons;
    std::vector<float> xyz;  // for nanoflann
    std::vector<std::array<float, 3>> queryPoints;
};

const Data& mapData(const std::string& name) {
    static std::map<std::string, Data> cache;
    auto it = cache.find(name);
    if (it != cache.end()) return it->second;
    Data& d = cache[name];
    std::mt19937_64 rng(name == "box" ? 1 : 2);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    auto draw = [&](float p[3]) {
        if (name == "box") p[0] = u(rng), p[1] = u(rng), p[2] = u(rng);
        else onWalls(rng, p);
    };
    d.photons.resize(kPhotons);
    for (auto& ph : d.photons) {
        float p[3];
        draw(p);
        ph = PclPhoton{};
        ph.x = p[0], ph.y = p[1], ph.z = p[2];
        d.xyz.insert(d.xyz.end(), p, p + 3);
    }
    d.queryPoints.resize(kQueries);
    for (auto& q : d.queryPoints) draw(q.data());
    return d;
}

// The radius expected to hold 2k photons: density n per unit volume (box) or per unit area
// over 6 unit faces (walls; a disc of the ball on a face).
float radiusFor(const std::string& name, uint32_t k) {
    if (name == "box") return float(std::cbrt(2.0 * k / (kPhotons * 4.0 / 3.0 * kPi)));
    return float(std::sqrt(2.0 * k / (kPhotons / 6.0 * kPi)));
}

std::vector<PclKnnQuery> queries(const std::string& name, uint32_t k) {
    const float r = radiusFor(name, k);
    std::vector<PclKnnQuery> qs;
    for (const auto& p : mapData(name).queryPoints) {
        PclKnnQuery q{};
        q.x = p[0], q.y = p[1], q.z = p[2];
        q.maxRadius2 = r * r;
        q.k = k;
        qs.push_back(q);
    }
    return qs;
}

// The queries as render orders its searches (pipeline/query_order: the Morton code of their
// cell of side r_max / 4, ties in drawing order): neighbouring work-items then read the same
// nodes and photons. The bench's queries are drawn at random, the worst order for a search.
float orderCell(const std::string& name, uint32_t k) { return radiusFor(name, k) / 4.0f; }

std::vector<PclEstimateQuery> asEstimateQueries(const std::vector<PclKnnQuery>& qs) {
    std::vector<PclEstimateQuery> es(qs.size());
    for (size_t i = 0; i < qs.size(); ++i) {
        es[i] = PclEstimateQuery{};
        es[i].x = qs[i].x, es[i].y = qs[i].y, es[i].z = qs[i].z;
        es[i].maxRadius2 = qs[i].maxRadius2;
        es[i].k = qs[i].k;
    }
    return es;
}

// order[s]: the query at position s of that order (the device's own sort).
std::vector<uint32_t> queryOrder(const std::string& name, uint32_t k) {
    Device& dev = device();
    const std::vector<PclKnnQuery> qs = queries(name, k);
    cl::Buffer es = dev.upload(asEstimateQueries(qs));
    const QueryOrder o = orderQueries(dev, es, qs.size(), orderCell(name, k));
    return dev.download<uint32_t>(o.order, qs.size());
}

struct Cloud {
    const std::vector<float>* xyz;
    size_t kdtree_get_point_count() const { return xyz->size() / 3; }
    float kdtree_get_pt(size_t i, size_t dim) const { return (*xyz)[3 * i + dim]; }
    template <class B>
    bool kdtree_get_bbox(B&) const {
        return false;
    }
};
using NanoTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>, Cloud, 3, uint32_t>;

// ordered: the queries in render's order, and each run also orders them on the device (the
// sort's time counts as the search's: queries_per_s and queries_per_cpu_s include it; order_ms
// is its share).
void BM_DeviceKnn(benchmark::State& state, std::string name, KnnStructure s, uint32_t k, bool ordered) {
    Device& dev = device();
    const Data& d = mapData(name);
    std::vector<PclKnnQuery> qs = queries(name, k);
    cl::Buffer estimateQueries = dev.upload(asEstimateQueries(qs));
    if (ordered) {
        const std::vector<PclKnnQuery> drawn = qs;
        const std::vector<uint32_t> order = queryOrder(name, k);
        for (size_t i = 0; i < qs.size(); ++i) qs[i] = drawn[order[i]];
    }
    cl::Buffer photons = dev.upload(d.photons);
    cl::Buffer qbuf = dev.upload(qs);
    KnnKdTree tree;
    DeviceHashGrid grid;
    if (s == KnnStructure::KdTree) tree = packKdTree(dev, buildKdTree(dev, photons, d.photons.size()));
    else grid = buildHashGrid(dev, photons, d.photons.size(), hashGridParams(d.photons, radiusFor(name, k)));
    DeviceKnnOutput out;
    // Warm-up: the program build for this heap capacity.
    if (s == KnnStructure::KdTree) knnSearchKdTree(dev, tree, qbuf, 64, k, out);
    else knnSearchHashGrid(dev, grid, qbuf, 64, k, out);
    double kernel = 0, cpu = 0, sorting = 0;
    size_t done = 0;
    for (auto _ : state) {
        const double c0 = cpuSeconds();
        double t = 0;
        if (ordered) {
            const auto w0 = std::chrono::steady_clock::now();
            const QueryOrder o = orderQueries(dev, estimateQueries, qs.size(), orderCell(name, k));
            dev.finish();
            t = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
            sorting += t;
        }
        t += s == KnnStructure::KdTree ? knnSearchKdTree(dev, tree, qbuf, qs.size(), k, out)
                                       : knnSearchHashGrid(dev, grid, qbuf, qs.size(), k, out);
        cpu += cpuSeconds() - c0;
        kernel += t;
        done += qs.size();
        state.SetIterationTime(t);
    }
    if (ordered) state.counters["order_ms"] = 1e3 * sorting / double(state.iterations());
    const std::vector<uint32_t> counts = dev.download<uint32_t>(out.counts, qs.size());
    double found = 0;
    for (uint32_t c : counts) found += c;
    state.counters["queries_per_s"] = done / kernel;
    state.counters["queries_per_cpu_s"] = done / cpu;
    state.counters["mean_found"] = found / qs.size();
    state.counters["r_max"] = radiusFor(name, k);
    const std::string tag = std::string(s == KnnStructure::KdTree ? "kdtree" : "grid") + (ordered ? "-ordered" : "");
    rates()[tag + "/" + name + "/" + std::to_string(k)] = done / cpu;
    rates()[tag + "-wall/" + name + "/" + std::to_string(k)] = done / kernel;
}

// bounded: the search starts with r_max² as its worst distance (KNNResultSet's last slot), so
// it prunes by the radius before k are found, as the device searches do.
size_t nanoKnn(const NanoTree& tree, const float* q, uint32_t k, float maxRadius2, bool bounded, uint32_t* idx,
               float* dist) {
    if (!bounded) return tree.knnSearch(q, k, idx, dist);
    nanoflann::KNNResultSet<float, uint32_t> set(k);
    set.init(idx, dist);
    dist[k - 1] = maxRadius2;
    tree.findNeighbors(set, q, nanoflann::SearchParams());
    return set.size();
}

// ordered: the same queries in render's order (the order computed once, not timed).
void BM_Nanoflann(benchmark::State& state, std::string name, uint32_t k, bool bounded, bool ordered) {
    const Data& d = mapData(name);
    std::vector<std::array<float, 3>> points = d.queryPoints;
    if (ordered) {
        const std::vector<uint32_t> order = queryOrder(name, k);
        for (size_t i = 0; i < points.size(); ++i) points[i] = d.queryPoints[order[i]];
    }
    Cloud cloud{&d.xyz};
    NanoTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    std::vector<uint32_t> idx(kQueries * size_t(k));
    std::vector<float> dist(kQueries * size_t(k));
    std::vector<size_t> found(threads, 0);
    const float r2 = radiusFor(name, k) * radiusFor(name, k);
    double wall = 0, cpu = 0;
    size_t done = 0;
    for (auto _ : state) {
        const double c0 = cpuSeconds();
        const auto w0 = std::chrono::steady_clock::now();
        std::vector<std::thread> pool;
        for (unsigned t = 0; t < threads; ++t)
            pool.emplace_back([&, t] {
                size_t f = 0;
                for (size_t q = t * kQueries / threads; q < (t + 1) * kQueries / threads; ++q)
                    f += nanoKnn(tree, points[q].data(), k, r2, bounded, &idx[q * k], &dist[q * k]);
                found[t] = f;
            });
        for (auto& th : pool) th.join();
        const double w = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
        wall += w;
        cpu += cpuSeconds() - c0;
        done += kQueries;
        state.SetIterationTime(w);
    }
    state.counters["queries_per_s"] = done / wall;
    state.counters["queries_per_cpu_s"] = done / cpu;
    state.counters["threads"] = threads;
    const std::string tag = std::string(bounded ? "nanoflann-r" : "nanoflann") + (ordered ? "-ordered" : "");
    rates()[tag + "/" + name + "/" + std::to_string(k)] = done / cpu;
    rates()[tag + "-wall/" + name + "/" + std::to_string(k)] = done / wall;
}

void BM_Build(benchmark::State& state, std::string name, std::string what) {
    const Data& d = mapData(name);
    Device& dev = device();
    cl::Buffer photons = dev.upload(d.photons);
    const PclGridParams params = hashGridParams(d.photons, radiusFor(name, 100));
    if (what == "grid") buildHashGrid(dev, photons, d.photons.size(), params);  // warm-up: program builds
    if (what == "kdtree") buildKdTree(dev, photons, d.photons.size());
    double keys = 0, sort = 0, ranges = 0;
    for (auto _ : state) {
        const auto w0 = std::chrono::steady_clock::now();
        if (what == "grid") {
            DeviceHashGrid g = buildHashGrid(dev, photons, d.photons.size(), params);
            dev.finish();
            keys += g.keySeconds, sort += g.sortSeconds, ranges += g.rangeSeconds;
        } else if (what == "kdtree") {
            DeviceKdTree t = buildKdTree(dev, photons, d.photons.size());
            dev.finish();
        } else {
            Cloud cloud{&d.xyz};
            NanoTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
            benchmark::DoNotOptimize(tree.root_node);
        }
        state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count());
    }
    if (what == "grid") {  // device milliseconds per build by step (the rest of the wall time: host and launches)
        const double runs = double(state.iterations());
        state.counters["keys_ms"] = 1e3 * keys / runs;
        state.counters["sort_ms"] = 1e3 * sort / runs;
        state.counters["ranges_ms"] = 1e3 * ranges / runs;
    }
}

const char* kMaps[] = {"box", "walls"};
const uint32_t kKs[] = {50, 100, 500};

void registerAll() {
    for (const char* m : kMaps) {
        for (const char* what : {"grid", "kdtree", "nanoflann"})
            benchmark::RegisterBenchmark((std::string("Build/") + what + "/" + m).c_str(), BM_Build, std::string(m),
                                         std::string(what))
                ->Unit(benchmark::kMillisecond)
                ->UseManualTime()
                ->Iterations(3);
        for (uint32_t k : kKs) {
            for (bool ordered : {false, true}) {
                const std::string suffix = std::string(m) + "/k" + std::to_string(k) + (ordered ? "/ordered" : "");
                benchmark::RegisterBenchmark(("KdTree/" + suffix).c_str(), BM_DeviceKnn, std::string(m),
                                             KnnStructure::KdTree, k, ordered)
                    ->Unit(benchmark::kMillisecond)
                    ->UseManualTime()
                    ->Iterations(2);
                benchmark::RegisterBenchmark(("HashGrid/" + suffix).c_str(), BM_DeviceKnn, std::string(m),
                                             KnnStructure::HashGrid, k, ordered)
                    ->Unit(benchmark::kMillisecond)
                    ->UseManualTime()
                    ->Iterations(2);
                benchmark::RegisterBenchmark(("Nanoflann/" + suffix).c_str(), BM_Nanoflann, std::string(m), k, false,
                                             ordered)
                    ->Unit(benchmark::kMillisecond)
                    ->UseManualTime()
                    ->Iterations(2);
                benchmark::RegisterBenchmark(("NanoflannRmax/" + suffix).c_str(), BM_Nanoflann, std::string(m), k, true,
                                             ordered)
                    ->Unit(benchmark::kMillisecond)
                    ->UseManualTime()
                    ->Iterations(2);
            }
        }
    }
}

}  // namespace
}  // namespace pcl

int main(int argc, char** argv) {
    pcl::bench::runBenchmarks(argc, argv, pcl::registerAll);
    auto& r = pcl::rates();
    for (const char* m : pcl::kMaps)
        for (uint32_t k : pcl::kKs)
            for (const std::string order : {"", "-ordered"}) {
                const std::string key = std::string(m) + "/" + std::to_string(k);
                auto n = r.find("nanoflann" + order + "/" + key), t = r.find("kdtree" + order + "/" + key),
                     g = r.find("grid" + order + "/" + key);
                auto nr = r.find("nanoflann-r" + order + "/" + key);
                auto nw = r.find("nanoflann" + order + "-wall/" + key), tw = r.find("kdtree" + order + "-wall/" + key),
                     gw = r.find("grid" + order + "-wall/" + key);
                auto nrw = r.find("nanoflann-r" + order + "-wall/" + key);
                if (n == r.end() || t == r.end() || g == r.end() || nr == r.end()) continue;
                const double best = std::max(n->second, nr->second);
                std::printf("knn %s k=%u%s queries per CPU-second: kd-tree %.0f, grid %.0f, nanoflann %.0f "
                            "(r_max-bounded %.0f); device / faster nanoflann: kd-tree %.2f, grid %.2f | wall: kd-tree "
                            "%.0f, grid %.0f, nanoflann %.0f (bounded %.0f)/s\n",
                            m, k, order.empty() ? "" : " (queries in render's order; the device's includes its sort)",
                            t->second, g->second, n->second, nr->second, t->second / best, g->second / best, tw->second,
                            gw->second, nw->second, nrw->second);
            }
    return 0;
}
