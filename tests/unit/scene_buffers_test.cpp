// Flat scene buffers and photon allocation (kernels/README.md).
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "prep/photon_allocation.h"
#include "prep/scene_buffers.h"
#include "scene/load_scene.h"

namespace pcl {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(PhotonAllocation, SharesFollowWeightsExactlyAndSumToTheTotal) {
    std::vector<double> w = {1.0, 2.0, 3.0, 0.0, 4.0};
    auto first = allocatePhotons(w, 1000);
    ASSERT_EQ(first.size(), 6u);
    EXPECT_EQ(first.back(), 1000u);
    EXPECT_EQ(first[1] - first[0], 100u);
    EXPECT_EQ(first[2] - first[1], 200u);
    EXPECT_EQ(first[3] - first[2], 300u);
    EXPECT_EQ(first[4] - first[3], 0u);  // no power, no photons
    EXPECT_EQ(first[5] - first[4], 400u);
}

TEST(PhotonAllocation, RemaindersGoToTheLargestFractionsAndWeakLightsGetOne) {
    auto first = allocatePhotons({1.0, 1.0, 1.0}, 10);  // 3.33 each: one extra to the lowest index
    EXPECT_EQ(first[1] - first[0], 4u);
    EXPECT_EQ(first[2] - first[1], 3u);
    EXPECT_EQ(first[3] - first[2], 3u);
    auto weak = allocatePhotons({1.0, 1e-9}, 100);
    EXPECT_EQ(weak[2] - weak[1], 1u);
    EXPECT_EQ(weak[2], 100u);
}

TEST(SceneBuffers, LightPowersMatchTheSceneWithinFloatPrecision) {
    Scene scene = loadScene(std::string(PHOTONCL_SOURCE_DIR) + "/scenes/cornell-box.json");
    SceneGeometry geometry = SceneGeometry::build(scene);
    SceneBuffers b = buildSceneBuffers(scene, geometry);
    ASSERT_EQ(b.primInfo.size(), geometry.primitiveCount());
    ASSERT_FALSE(b.lights.empty());
    // Area light: Φ = π L A summed over its triangles.
    double expected = 0.0;
    for (const Light& l : scene.lights) {
        ASSERT_EQ(l.type, LightType::Area);
        const TriangleMesh& m = scene.meshes[l.mesh];
        double area = 0.0;
        for (size_t t = 0; t < m.triangleCount(); ++t) {
            Vec3 p0 = m.positions[m.indices[3 * t]];
            area += 0.5 * length(cross(m.positions[m.indices[3 * t + 1]] - p0, m.positions[m.indices[3 * t + 2]] - p0));
        }
        expected += kPi * area *
                    (scene.materials[m.material].emission.x + scene.materials[m.material].emission.y +
                     scene.materials[m.material].emission.z) /
                    3.0;
    }
    double got = 0.0;
    for (const PclLight& l : b.lights) {
        got += scalarPower(l);
        EXPECT_NEAR(std::sqrt(l.axis[0] * l.axis[0] + l.axis[1] * l.axis[1] + l.axis[2] * l.axis[2]), 1.0, 1e-6);
        EXPECT_LT(l.prim, geometry.triangleCount());
        // The emitting side: the light's normal equals its triangle's geometric normal.
        const PclPrimInfo& info = b.primInfo[l.prim];
        EXPECT_NEAR(info.a * l.axis[0] + info.b * l.axis[1] + info.c * l.axis[2], 1.0, 1e-5);
    }
    EXPECT_NEAR(got, expected, 1e-5 * expected);
    EXPECT_GT(b.rayEpsilon, 0.0f);
}

TEST(SceneBuffers, PointSpotAndDirectionalPowers) {
    Scene scene;
    scene.materials.push_back({});
    TriangleMesh floor;
    floor.positions = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}};
    floor.indices = {0, 1, 2};
    scene.meshes.push_back(floor);
    Light point;
    point.type = LightType::Point;
    point.intensity = Vec3(2.0f);
    Light spot;
    spot.type = LightType::Spot;
    spot.intensity = Vec3(1.0f);
    spot.cosInner = std::cos(0.3f);
    spot.cosOuter = std::cos(0.5f);
    Light sun;
    sun.type = LightType::Directional;
    sun.irradiance = Vec3(3.0f);
    scene.lights = {point, spot, sun};
    SceneGeometry geometry = SceneGeometry::build(scene);
    SceneBuffers b = buildSceneBuffers(scene, geometry);
    ASSERT_EQ(b.lights.size(), 3u);
    EXPECT_NEAR(b.lights[0].power[0], 8.0 * kPi, 1e-5);
    // Spot: ∫ smoothstep falloff over the cone, by quadrature in cosθ.
    double integral = 0.0;
    const int steps = 200000;
    for (int i = 0; i < steps; ++i) {
        double c = std::cos(0.5) + (1.0 - std::cos(0.5)) * (i + 0.5) / steps;
        double t = std::clamp((c - std::cos(0.5)) / (std::cos(0.3) - std::cos(0.5)), 0.0, 1.0);
        integral += t * t * (3 - 2 * t) * (1.0 - std::cos(0.5)) / steps;
    }
    EXPECT_NEAR(b.lights[1].power[0], 2.0 * kPi * integral, 1e-4 * b.lights[1].power[0]);
    EXPECT_NEAR(b.lights[2].power[0], 3.0 * kPi * b.sceneRadius * b.sceneRadius, 1e-4 * b.lights[2].power[0]);
}

}  // namespace
}  // namespace pcl
