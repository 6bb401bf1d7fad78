// BVH benchmarks: build time, SAH cost and bytes per triangle for a generated 1M-triangle mesh,
// and closest-hit rays per second of the host traversal, the traversal kernel (PoCL or whatever
// device `auto` opens) and Embree's rtcIntersect1 (Embree builds its own BVH) on the same rays.
// All traversals run on every hardware thread and are timed by the CPU time of the whole
// process (every thread: PoCL's workers, Embree's, ours), so rays_per_s is rays per CPU-second
// and the ratios hold on a machine shared with other work; on an idle machine multiply by the
// core count for wall-clock rays per second.
//
//   bvh_bench --benchmark_filter=Build     build figures only
//   counters: rays_per_s, bytes_per_tri, sah, build_s, nodes, packets
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <random>
#include <thread>

#include "bench_common.h"
#include "bench_meshes.h"
#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "pipeline/intersect.h"
#include "reference/parallel_for.h"
#include "reference/surface.h"
#if __has_include("scene/load_scene.h")
#include "scene/load_scene.h"
#define PCL_HAVE_LOAD_SCENE 1
#endif
#ifdef PHOTONCL_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace pcl {
namespace {

constexpr size_t kRays = 1 << 18;

Scene mesh1M() {
    Scene s;
    s.meshes.push_back(displacedSphere(500, 1000));
    s.camera.position = {0, 0.5f, 3.0f};
    s.camera.lookAt = {0, 0, 0};
    return s;
}

// The scenes by name: "mesh1M" (generated) or a shipped scene file stem.
const Scene* scene(const std::string& name) {
    static std::map<std::string, std::unique_ptr<Scene>> cache;
    auto it = cache.find(name);
    if (it != cache.end()) return it->second.get();
    std::unique_ptr<Scene> s;
    if (name == "mesh1M") {
        s = std::make_unique<Scene>(mesh1M());
    } else {
#ifdef PCL_HAVE_LOAD_SCENE
        auto path = std::filesystem::path(PHOTONCL_SOURCE_DIR) / "scenes" / (name + ".json");
        if (std::filesystem::exists(path)) s = std::make_unique<Scene>(loadScene(path.string()));
#endif
    }
    return cache.emplace(name, std::move(s)).first->second.get();
}

const SceneGeometry& geometry(const std::string& name) {
    static std::map<std::string, std::unique_ptr<SceneGeometry>> cache;
    auto& g = cache[name];
    if (!g) g = std::make_unique<SceneGeometry>(SceneGeometry::build(*scene(name)));
    return *g;
}

// Half camera-like rays from outside towards random points of the scene, half random rays from
// inside its bounds: the mix a photon pass and a camera pass make.
const std::vector<PclRay>& rays(const std::string& name) {
    static std::map<std::string, std::vector<PclRay>> cache;
    auto& out = cache[name];
    if (!out.empty()) return out;
    const SceneGeometry& g = geometry(name);
    Bounds3 b = g.bounds();
    std::mt19937 rng(42);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    out.resize(kRays);
    const Vec3 eye = scene(name)->camera.position;
    for (size_t i = 0; i < kRays; ++i) {
        Vec3 target = b.lo + Vec3(u(rng), u(rng), u(rng)) * b.extent();
        Vec3 o = (i % 2) ? eye : b.lo + Vec3(u(rng), u(rng), u(rng)) * b.extent();
        Vec3 d = (i % 2) ? target - o : Vec3(u(rng) * 2 - 1, u(rng) * 2 - 1, u(rng) * 2 - 1);
        PclRay r = makeRay(o, d, u(rng));
        out[i] = r;
    }
    return out;
}

void BM_Build(benchmark::State& state, const std::string& name) {
    const Scene* s = scene(name);
    if (!s) {
        state.SkipWithError("scene not found");
        return;
    }
    BvhStats st;
    for (auto _ : state) {
        SceneGeometry g = SceneGeometry::build(*s);
        st = g.stats();
        benchmark::DoNotOptimize(g.nodes.data());
    }
    state.counters["triangles"] = double(s->triangleCount());
    state.counters["build_s"] = st.buildSeconds;
    state.counters["sah"] = st.sahCost;
    state.counters["bytes_per_tri"] = st.bytesPerTriangle();
    state.counters["nodes"] = double(st.nodes);
    state.counters["packets"] = double(st.packets);
    state.counters["fill"] = double(st.triangles) / (4.0 * double(std::max<size_t>(st.packets, 1)));
    state.counters["depth"] = st.depth;
    state.counters["max_stack"] = st.maxStack;
}

void BM_HostClosest(benchmark::State& state, const std::string& name) {
    if (!scene(name)) {
        state.SkipWithError("scene not found");
        return;
    }
    const SceneGeometry& g = geometry(name);
    const auto& rs = rays(name);
    std::vector<PclHit> hits(rs.size());
    for (auto _ : state) parallelForEveryThread(rs.size(), [&](size_t i) { g.intersect(rs[i], hits[i]); });
    state.counters["rays_per_s"] = benchmark::Counter(double(rs.size()), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_KernelClosest(benchmark::State& state, const std::string& name) {
    if (!scene(name)) {
        state.SkipWithError("scene not found");
        return;
    }
    Device& device = bench::device();
    const SceneGeometry& g = geometry(name);
    const auto& rs = rays(name);
    DeviceGeometry dg(device, g);
    cl::Buffer rayBuf = device.upload(rs);
    cl::Buffer hitBuf = device.allocate<PclHit>(rs.size());
    intersectBuffers(device, dg, rayBuf, hitBuf, rs.size(), false);  // warm-up: build, first touch
    for (auto _ : state) {
        intersectBuffers(device, dg, rayBuf, hitBuf, rs.size(), false);
        device.finish();
    }
    state.counters["rays_per_s"] = benchmark::Counter(double(rs.size()), benchmark::Counter::kIsIterationInvariantRate);
    state.SetLabel(device.info().name);
}

#ifdef PHOTONCL_HAVE_EMBREE
// Embree peer on the same triangles and spheres (Embree's built-in sphere points), static
// geometry: motion is left out (the benchmark scenes have none).
void BM_EmbreeClosest(benchmark::State& state, const std::string& name) {
    const Scene* s = scene(name);
    if (!s) {
        state.SkipWithError("scene not found");
        return;
    }
    RTCDevice dev = rtcNewDevice(nullptr);
    RTCScene rs = rtcNewScene(dev);
    rtcSetSceneBuildQuality(rs, RTC_BUILD_QUALITY_HIGH);
    for (const auto& m : s->meshes) {
        if (m.indices.empty()) continue;
        RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), m.positions.size()));
        for (size_t i = 0; i < m.positions.size(); ++i) {
            v[3 * i] = m.positions[i].x;
            v[3 * i + 1] = m.positions[i].y;
            v[3 * i + 2] = m.positions[i].z;
        }
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), m.triangleCount()));
        std::copy(m.indices.begin(), m.indices.end(), idx);
        rtcCommitGeometry(geom);
        rtcAttachGeometry(rs, geom);
        rtcReleaseGeometry(geom);
    }
    if (!s->spheres.empty()) {
        RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                              4 * sizeof(float), s->spheres.size()));
        for (size_t i = 0; i < s->spheres.size(); ++i) {
            const Sphere& sp = s->spheres[i];
            v[4 * i] = sp.centre.x;
            v[4 * i + 1] = sp.centre.y;
            v[4 * i + 2] = sp.centre.z;
            v[4 * i + 3] = sp.radius;
        }
        rtcCommitGeometry(geom);
        rtcAttachGeometry(rs, geom);
        rtcReleaseGeometry(geom);
    }
    rtcCommitScene(rs);
    const auto& rays_ = rays(name);
    std::vector<float> tfar(rays_.size());
    for (auto _ : state) {
        parallelForEveryThread(rays_.size(), [&](size_t i) {
            const PclRay& r = rays_[i];
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            RTCRayHit rh{};
            rh.ray.org_x = r.ox;
            rh.ray.org_y = r.oy;
            rh.ray.org_z = r.oz;
            rh.ray.dir_x = r.dx;
            rh.ray.dir_y = r.dy;
            rh.ray.dir_z = r.dz;
            rh.ray.tnear = r.tmin;
            rh.ray.tfar = r.tmax;
            rh.ray.mask = 0xFFFFFFFFu;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(rs, &ctx, &rh);
            tfar[i] = rh.ray.tfar;
        });
    }
    state.counters["rays_per_s"] =
        benchmark::Counter(double(rays_.size()), benchmark::Counter::kIsIterationInvariantRate);
    rtcReleaseScene(rs);
    rtcReleaseDevice(dev);
}
#endif

void registerAll() {
    benchmark::RegisterBenchmark("Build/mesh1M", BM_Build, std::string("mesh1M"))
        ->Unit(benchmark::kMillisecond)
        ->Iterations(3);
    for (const char* name : {"cornell-spheres", "cornell-box", "mesh1M"}) {
        std::string n = name;
        benchmark::RegisterBenchmark(("HostClosest/" + n).c_str(), BM_HostClosest, n)
            ->Unit(benchmark::kMillisecond)
            ->MeasureProcessCPUTime()
            ->MinTime(2.0);
        benchmark::RegisterBenchmark(("KernelClosest/" + n).c_str(), BM_KernelClosest, n)
            ->Unit(benchmark::kMillisecond)
            ->MeasureProcessCPUTime()
            ->MinTime(2.0);
#ifdef PHOTONCL_HAVE_EMBREE
        benchmark::RegisterBenchmark(("EmbreeClosest/" + n).c_str(), BM_EmbreeClosest, n)
            ->Unit(benchmark::kMillisecond)
            ->MeasureProcessCPUTime()
            ->MinTime(2.0);
#endif
    }
}

}  // namespace
}  // namespace pcl

int main(int argc, char** argv) {
    pcl::bench::runBenchmarks(argc, argv, pcl::registerAll);
    return 0;
}
