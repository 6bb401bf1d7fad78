// Direct light (kernels/direct_light.cl) against the twin (reference/direct_light), and analytic
// checks on a diffuse plane: a point light gives L = ρ/π I cosθ/d², a spot the same inside its
// cone and 0 outside, a directional light ρ/π E cosθ, and a square area light the exact on-axis
// irradiance (form factor) in the mean of its area samples, with and without MIS.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "check/on_device.h"
#include "check/render.h"
#include "eye_test_scenes.h"
#include "pipeline/camera_rays.h"
#include "pipeline/direct_light.h"
#include "pipeline/eye_paths.h"
#include "reference/direct_light.h"

namespace pcl {
namespace {

void twinMatch(const char* name) {
    test::BuiltScene b = test::shippedScene(name, 48, 36);
    const PclCameraParams cp = cameraParams(b.scene.camera, true, true, eyePassSeed(5, 2), 2);
    const std::vector<PclRay> rays = cameraRaysOnDevice(test::testDevice(), cp);
    const AreaLightTable table = buildAreaLightTable(b.buffers, b.geometry.primitiveCount());
    const PclEyeParams ep = eyeParams(cp, b.geometry, b.buffers, table);
    const std::vector<PclEyeHit> hits = eyePathsOnDevice(test::testDevice(), b.geometry, b.buffers, rays, ep);
    for (uint32_t N : {0u, 16u}) {
        const PclDirectParams dp = directParams(ep, b.geometry, b.buffers, table, 4, N);
        const std::vector<PclRadiance> d = directLightOnDevice(test::testDevice(), b.geometry, b.buffers, hits, dp);
        const std::vector<PclRadiance> t = referenceDirectLight(b.geometry, b.buffers, hits, dp);
        const StageComparison c = compareRadiance("direct", d, t, 1e-3, 3);
        std::printf("[figure] direct light %s 48x36 2x2 M=4 N=%u: %.4f %% of %zu within 1e-3 (%zu nonzero), max rel "
                    "%.3e, %zu NaN/Inf\n",
                    name, N, 100.0 * c.fraction(), c.compared, c.nonzero, c.maxRelError, c.nonFinite);
        EXPECT_GE(c.fraction(), 0.999);
        EXPECT_EQ(c.nonFinite, 0u);
        EXPECT_GT(c.nonzero, c.compared / 4);
    }
}

TEST(DirectLight, DeviceMatchesTwinCornellBox) { twinMatch("cornell-box.json"); }
TEST(DirectLight, DeviceMatchesTwinCornellSpheresPoint) { twinMatch("cornell-spheres-point.json"); }

// A large diffuse floor y = 0 (normal +y) and the given lights.
test::BuiltScene floorScene(const std::vector<Light>& lights, bool areaLight = false, float h = 1.0f, float a = 0.5f,
                            float Le = 2.0f) {
    Scene s;
    s.camera.position = Vec3(0, 5, 5);
    s.camera.lookAt = Vec3(0.0f);
    s.camera.width = s.camera.height = 8;
    const int floor = test::addMaterial(s, Vec3(0.5f));
    TriangleMesh m;
    m.material = floor;
    test::addQuad(m, Vec3(-50, 0, -50), Vec3(-50, 0, 50), Vec3(50, 0, 50), Vec3(50, 0, -50));
    s.meshes.push_back(m);
    s.lights = lights;
    if (areaLight) test::addAreaLight(s, h, a, Vec3(Le));
    return test::build(s);
}

std::vector<PclEyeHit> floorHits(int n, float extent) {
    std::vector<PclEyeHit> hits;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            hits.push_back(test::handMadeHit(Vec3(extent * (2.0f * (i + 0.5f) / n - 1.0f), 0.0f,
                                                  extent * (2.0f * (j + 0.5f) / n - 1.0f)),
                                             Vec3(0, 1, 0), 0.5f, uint32_t(hits.size()), 0));
    return hits;
}

std::vector<PclRadiance> runDirect(const test::BuiltScene& b, const std::vector<PclEyeHit>& hits, uint32_t M,
                                   uint32_t N) {
    PclEyeParams ep{};
    ep.samplesPerPixel = 1;
    ep.sampleCount = uint32_t(hits.size());
    ep.seedLo = 17;
    const AreaLightTable table = buildAreaLightTable(b.buffers, b.geometry.primitiveCount());
    const PclDirectParams dp = directParams(ep, b.geometry, b.buffers, table, M, N);
    return directLightOnDevice(test::testDevice(), b.geometry, b.buffers, hits, dp);
}

TEST(DirectLight, PointSpotAndDirectionalLightsAreExact) {
    const Vec3 P(0.3f, 2.0f, -0.2f), I(3.0f, 2.0f, 1.0f);
    const std::vector<PclEyeHit> hits = floorHits(16, 3.0f);
    double worst = 0.0;
    // Point.
    {
        const std::vector<PclRadiance> L = runDirect(floorScene({test::pointLight(P, I)}), hits, 1, 0);
        for (size_t i = 0; i < hits.size(); ++i) {
            const Vec3 d = P - Vec3(hits[i].x, hits[i].y, hits[i].z);
            const double d2 = dot(d, d), cosT = d.y / std::sqrt(d2);
            const double expect = 0.5 / M_PI * I.x * cosT / d2;
            worst = std::max(worst, std::fabs(L[i].r - expect) / expect);
            EXPECT_NEAR(L[i].b / L[i].r, 1.0 / 3.0, 1e-5);
        }
    }
    // Spot pointing down: full inside cosInner, 0 outside cosOuter.
    {
        const float ci = std::cos(0.5f), co = std::cos(0.6f);
        const std::vector<PclRadiance> L =
            runDirect(floorScene({test::spotLight(P, Vec3(0, -1, 0), I, ci, co)}), hits, 1, 0);
        size_t inside = 0, outside = 0;
        for (size_t i = 0; i < hits.size(); ++i) {
            const Vec3 d = P - Vec3(hits[i].x, hits[i].y, hits[i].z);
            const double d2 = dot(d, d), cosT = d.y / std::sqrt(d2);
            if (cosT >= ci + 1e-4) {
                const double expect = 0.5 / M_PI * I.x * cosT / d2;
                worst = std::max(worst, std::fabs(L[i].r - expect) / expect);
                ++inside;
            } else if (cosT <= co - 1e-4) {
                EXPECT_EQ(L[i].r, 0.0f);
                ++outside;
            }
        }
        EXPECT_GT(inside, 4u);
        EXPECT_GT(outside, 4u);
    }
    // Directional.
    {
        Light l;
        l.type = LightType::Directional;
        l.direction = normalize(Vec3(0.3f, -1.0f, 0.2f));
        l.irradiance = Vec3(2.0f);
        const std::vector<PclRadiance> L = runDirect(floorScene({l}), hits, 1, 0);
        const double expect = 0.5 / M_PI * 2.0 * -l.direction.y;
        for (size_t i = 0; i < hits.size(); ++i) worst = std::max(worst, std::fabs(L[i].r - expect) / expect);
    }
    std::printf(
        "[figure] point/spot/directional over a plane: worst relative error %.3e vs ρ/π I cosθ/d², ρ/π E cosθ\n",
        worst);
    EXPECT_LT(worst, 1e-4);  // float E = Φ/(πR²) on the directional light's disc, I = Φ/4π
}

// E at the centre under a parallel square of side 2a at height h, radiance Le: 4 corner
// rectangles of a × a, each π Le F with F the corner form factor.
double squareIrradiance(double a, double h, double Le) {
    const double A = a / h, sa = std::sqrt(1 + A * A);
    const double F = (1.0 / (2 * M_PI)) * 2.0 * (A / sa * std::atan(A / sa));
    return 4.0 * M_PI * Le * F;
}

TEST(DirectLight, SquareAreaLightMatchesTheFormFactor) {
    const float h = 1.0f, a = 0.5f, Le = 2.0f;
    const test::BuiltScene b = floorScene({}, true, h, a, Le);
    std::vector<PclEyeHit> hits;
    for (uint32_t i = 0; i < 20000; ++i) hits.push_back(test::handMadeHit(Vec3(0.0f), Vec3(0, 1, 0), 0.5f, i, 0));
    const double expect = 0.5 / M_PI * squareIrradiance(a, h, Le);
    const double light = test::meanLuminance(runDirect(b, hits, 4, 0));
    std::printf(
        "[figure] square light (side %.1f at %.1f m, Le %.1f): light sampling mean %.5f, analytic %.5f (%.3f %%)\n",
        2 * a, h, Le, light, expect, 100.0 * (light / expect - 1.0));
    EXPECT_NEAR(light / expect, 1.0, 0.01);
}

}  // namespace
}  // namespace pcl
