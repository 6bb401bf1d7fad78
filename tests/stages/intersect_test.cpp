// Traversal kernel (kernels/intersect.cl) against the host traversal: 100 000 rays per shipped
// scene and per synthetic scene (triangles, spheres, moving primitives). Closest hit: same
// primitive id and t within 1e-5 relative; any hit: same existence. The kernel repeats the
// host's arithmetic operation for operation with FP_CONTRACT off (kernels/shared/bvh.h), so on
// a device with IEEE division and sqrt (PoCL) every count is expected to be 0 and is asserted 0.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>

#include "check/on_device.h"
#include "check/trace.h"
#include "common/test_scenes.h"
#include "device_fixture.h"
#include "pipeline/intersect.h"
#include "scene/load_scene.h"

namespace pcl {
namespace {

using test_scenes::randomSoup;
using test_scenes::shippedSceneFiles;

constexpr size_t kRays = 100000;

void expectKernelMatchesHost(const Scene& scene, const char* name, uint64_t seed) {
    SceneGeometry g = SceneGeometry::build(scene);
    IntersectCheckReport r = checkIntersect(test::testDevice(), scene, g, kRays, seed);
    std::printf("%s (%u primitives, stack %d)\n%s", name, g.primitiveCount(), g.stats().maxStack, r.table().c_str());
    size_t hits = 0;
    for (const auto& row : r.rows) {
        EXPECT_EQ(row.primMismatches, 0u) << name << " " << row.rays;
        EXPECT_EQ(row.tMismatches, 0u) << name << " " << row.rays;
        EXPECT_EQ(row.anyMismatches, 0u) << name << " " << row.rays;
        hits += row.hostHits;
    }
    EXPECT_GT(hits, kRays / 10) << name << ": too few hits for the check to mean much";
}

// Triangles and spheres, some of each moving, seen by a camera from outside.
Scene syntheticScene() {
    Scene s;
    s.meshes.push_back(randomSoup(4000, 1, 0.12f));
    s.meshes.push_back(randomSoup(1000, 2, 0.1f, Vec3(0.3f, 0.0f, -0.2f)));
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 300; ++i) {
        Sphere sp;
        sp.centre = Vec3(u(rng), u(rng), u(rng)) * 1.2f;
        sp.radius = 0.03f + 0.08f * std::fabs(u(rng));
        if (i % 3 == 0) sp.motion = Vec3(u(rng), u(rng), u(rng)) * 0.3f;
        s.spheres.push_back(sp);
    }
    s.camera.position = {0.5f, 0.8f, 4.0f};
    s.camera.lookAt = {0, 0, 0};
    return s;
}

TEST(Intersect, KernelMatchesHostOnSyntheticScene) { expectKernelMatchesHost(syntheticScene(), "synthetic", 1); }

TEST(Intersect, EmptySceneMissesOnDevice) {
    Scene s;
    SceneGeometry g = SceneGeometry::build(s);
    std::vector<PclRay> rays(100);
    for (auto& r : rays) {
        r = PclRay{};
        r.dx = 1.0f;
        r.tmax = INFINITY;
    }
    for (bool any : {false, true})
        for (const PclHit& h : intersectOnDevice(test::testDevice(), g, rays, any)) EXPECT_EQ(h.prim, PCL_NO_HIT);
}

TEST(Intersect, ChunkedLaunchCoversEveryRay) {
    // More rays than one launch takes: every ray of every chunk must be written.
    Scene s;
    s.spheres.push_back(Sphere{});
    SceneGeometry g = SceneGeometry::build(s);
    std::vector<PclRay> rays(kIntersectChunk + 1000);
    for (size_t i = 0; i < rays.size(); ++i) {
        rays[i] = PclRay{};
        rays[i].oz = -5.0f;
        rays[i].dz = 1.0f;
        rays[i].tmax = INFINITY;
    }
    std::vector<PclHit> hits = intersectOnDevice(test::testDevice(), g, rays, false);
    size_t wrong = 0;
    for (const PclHit& h : hits) wrong += h.prim != 0u || std::fabs(h.t - 4.0f) > 1e-6f;
    EXPECT_EQ(wrong, 0u);
}

TEST(Intersect, KernelMatchesHostOnShippedScenes) {
    std::vector<std::filesystem::path> files = shippedSceneFiles();
    ASSERT_FALSE(files.empty()) << "no shipped scenes found under scenes/";
    uint64_t seed = 100;
    for (const auto& path : files) expectKernelMatchesHost(loadScene(path.string()), path.filename().c_str(), seed++);
}

}  // namespace
}  // namespace pcl
