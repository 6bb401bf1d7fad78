// The reference path tracer under an environment light ("sky", prep/environment_map.h) against
// closed forms, with light sampling (MIS between the sky's samples and BSDF samples) and without
// (BSDF samples alone):
//  * a diffuse sphere alone under a constant sky: it never sees itself, so every point receives
//    E = π L and leaves ρ L; the background is L;
//  * a diffuse plane under a map dark but for one texel: E = L ∫_texel cos θ dω exactly, the
//    same within 1 % as a directional light of irradiance L Ω_texel from the texel's centre.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "accuracy/pixel_stats.h"
#include "common/test_scenes.h"
#include "core/math.h"
#include "reference/camera.h"

using namespace pcl;
using test_scenes::addMaterial;
using test_scenes::addQuad;
using test_scenes::addSphere;

namespace {

struct ZSummary {
    double worstZ = 0.0, meanRatio = 0.0;
    int count = 0;
};

// Pixels for which `expected` returns a value ≥ 0 (−1: skip), every channel.
template <class F>
ZSummary compare(const PixelStats& px, int width, int height, F expected) {
    ZSummary z;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const Vec3 e = expected(x, y);
            if (e.x < 0.0f) continue;
            const size_t p = size_t(y * width + x);
            for (int c = 0; c < 3; ++c) {
                const double se = std::max(double(px.stdError[p][c]), 1e-7 * e[c]);
                z.worstZ = std::max(z.worstZ, std::abs(px.mean[p][c] - e[c]) / se);
                z.meanRatio += px.mean[p][c] / e[c];
                ++z.count;
            }
        }
    z.meanRatio /= std::max(1, z.count);
    return z;
}

}  // namespace

TEST(EnvironmentLight, DiffuseSphereUnderAConstantSkyReflectsRhoL) {
    Scene scene;
    const Vec3 rho(0.2f, 0.5f, 0.8f), L(1.0f, 2.0f, 0.5f);
    addSphere(scene, Vec3(0.0f), 1.0f, addMaterial(scene, rho));
    scene.environment.scale = L;
    test_scenes::setCamera(scene, Vec3(0, 0.5f, 4), Vec3(0.0f), Vec3(0, 1, 0), 40.0f, 16, 16);
    for (bool lightSampling : {true, false}) {
        PathTracerSettings settings;
        settings.samplesPerPixel = testSpp(256);
        settings.seed = testSeed(21);
        settings.lightSampling = lightSampling;
        const PixelStats px = renderWithErrors(scene, settings);
        const ZSummary sphere = compare(px, 16, 16, [&](int x, int y) {
            return sphereCoverage(scene, x, y, 3) == 1 ? rho * L : Vec3(-1.0f);
        });
        const ZSummary sky =
            compare(px, 16, 16, [&](int x, int y) { return sphereCoverage(scene, x, y, 3) == 0 ? L : Vec3(-1.0f); });
        std::printf("constant sky, light sampling %d: sphere %d pixel-channels worst |z| %.2f mean ratio %.4f; sky %d "
                    "mean ratio %.6f\n",
                    int(lightSampling), sphere.count, sphere.worstZ, sphere.meanRatio, sky.count, sky.meanRatio);
        ASSERT_GT(sphere.count, 60);
        ASSERT_GT(sky.count, 60);
        EXPECT_LT(sphere.worstZ, 4.5);
        EXPECT_NEAR(sphere.meanRatio, 1.0, 0.01);
        EXPECT_NEAR(sky.meanRatio, 1.0, 1e-6);  // seen directly: exact
    }
}

TEST(EnvironmentLight, OneBrightTexelLightsAPlaneLikeADirectionalLight) {
    const test_scenes::OneTexelSkyPlane scenes = test_scenes::oneTexelSkyPlane(32, 16, 5, 3, 500.0f, 0.5f);
    const Scene& scene = scenes.sky;
    const float expected = scenes.expected;

    for (bool lightSampling : {true, false}) {
        PathTracerSettings settings;
        settings.samplesPerPixel = testSpp(lightSampling ? 64 : 4096);
        settings.seed = testSeed(22);
        settings.lightSampling = lightSampling;
        const PixelStats px = renderWithErrors(scene, settings);
        const ZSummary z = compare(px, 8, 8, [&](int, int) { return Vec3(expected); });
        std::printf("one bright texel, light sampling %d: %d pixel-channels worst |z| %.2f mean ratio %.5f\n",
                    int(lightSampling), z.count, z.worstZ, z.meanRatio);
        EXPECT_LT(z.worstZ, 4.5);
        EXPECT_NEAR(z.meanRatio, 1.0, lightSampling ? 0.005 : 0.05);  // BSDF samples alone rarely find the texel
    }

    // The directional light of irradiance V Ω_texel from the texel's centre direction.
    const Scene& sun = scenes.sun;
    PathTracerSettings settings;
    settings.samplesPerPixel = 4;
    const PixelStats px = renderWithErrors(sun, settings);
    const ZSummary z = compare(px, 8, 8, [&](int, int) { return Vec3(expected); });
    std::printf("directional light of the texel's irradiance: mean ratio to the texel's closed form %.5f\n",
                z.meanRatio);
    EXPECT_NEAR(z.meanRatio, 1.0, 0.01);
}
