// Camera rays (kernels/camera.cl) against the twin (reference/camera_rays) and analytic checks:
// every stratum of every pixel covered once, thin-lens rays of one film point meeting on the
// plane of focus, times uniform over the shutter, samplers the plan leaves out not run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>

#include "check/on_device.h"
#include "check/render.h"
#include "eye_test_scenes.h"
#include "pipeline/camera_rays.h"
#include "reference/camera_rays.h"

namespace pcl {
namespace {

TEST(CameraRays, DeviceMatchesTwinWithLensAndTime) {
    test::BuiltScene b = test::shippedScene("motion-dof.json", 48, 32);
    const PclCameraParams p = cameraParams(b.scene.camera, true, true, eyePassSeed(7, 3), 3);
    ASSERT_TRUE(p.lensSampling);
    const std::vector<PclRay> d = cameraRaysOnDevice(test::testDevice(), p);
    const std::vector<PclRay> t = referenceCameraRays(b.scene.camera, p);
    const StageComparison c = compareRays(d, t, 1e-3, 3);
    std::printf("[figure] camera rays motion-dof 48x32 3x3: %.4f %% of %zu within 1e-3, max rel %.3e\n",
                100.0 * c.fraction(), c.compared, c.maxRelError);
    EXPECT_GE(c.fraction(), 0.999);
    EXPECT_EQ(c.nonFinite, 0u);
}

// Film position of a pinhole ray, in pixels.
void filmPoint(const PclCameraParams& p, const PclRay& r, double& fx, double& fy) {
    const double f = r.dx * p.forward[0] + r.dy * p.forward[1] + r.dz * p.forward[2];
    const double sx = (r.dx * p.right[0] + r.dy * p.right[1] + r.dz * p.right[2]) / f;
    const double sy = (r.dx * p.up[0] + r.dy * p.up[1] + r.dz * p.up[2]) / f;
    fx = (sx / p.tanHalfWidth + 1.0) * 0.5 * p.width;
    fy = (1.0 - sy / p.tanHalfHeight) * 0.5 * p.height;
}

TEST(CameraRays, EveryStratumOfEveryPixelOnce) {
    test::BuiltScene b = test::shippedScene("cornell-box.json", 16, 12);
    const uint32_t n = 4;
    const PclCameraParams p = cameraParams(b.scene.camera, false, false, 11, n);
    const std::vector<PclRay> rays = cameraRaysOnDevice(test::testDevice(), p);
    ASSERT_EQ(rays.size(), size_t(16) * 12 * n * n);
    size_t wrong = 0;
    for (uint32_t pixel = 0; pixel < 16 * 12; ++pixel) {
        std::set<uint32_t> strata;
        for (uint32_t k = 0; k < n * n; ++k) {
            const PclRay& r = rays[pixel * n * n + k];
            double fx, fy;
            filmPoint(p, r, fx, fy);
            const double ux = (fx - pixel % 16) * n, uy = (fy - pixel / 16) * n;
            const int cx = int(std::floor(ux + 1e-9)), cy = int(std::floor(uy + 1e-9));
            // Inside stratum k (a point within 1e-3 of a stratum edge counts for either side).
            const bool inside = std::fabs(ux - (k % n + 0.5)) <= 0.5 + 1e-3 &&
                                std::fabs(uy - (k / n + 0.5)) <= 0.5 + 1e-3;
            if (!inside) ++wrong;
            strata.insert(uint32_t(std::min(std::max(cy, 0), int(n) - 1)) * n +
                          uint32_t(std::min(std::max(cx, 0), int(n) - 1)));
            EXPECT_EQ(r.ox, b.scene.camera.position.x);
            EXPECT_EQ(r.time, 0.0f);
        }
        EXPECT_EQ(strata.size(), size_t(n) * n) << "pixel " << pixel;
    }
    std::printf("[figure] camera strata 4x4 on 16x12: %zu samples outside their stratum\n", wrong);
    EXPECT_EQ(wrong, 0u);
}

TEST(CameraRays, ThinLensRaysMeetOnThePlaneOfFocus) {
    test::BuiltScene b = test::shippedScene("motion-dof.json", 32, 24);
    const PclCameraParams lens = cameraParams(b.scene.camera, true, true, 5, 2);
    const PclCameraParams pin = cameraParams(b.scene.camera, false, true, 5, 2);
    const std::vector<PclRay> a = cameraRaysOnDevice(test::testDevice(), lens);
    const std::vector<PclRay> c = cameraRaysOnDevice(test::testDevice(), pin);
    const Vec3 F(lens.forward[0], lens.forward[1], lens.forward[2]);
    const Vec3 eye = b.scene.camera.position;
    double worst = 0.0, maxOffset = 0.0, timeSum = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
        // Both rays at the plane dot(x − eye, F) = focusDistance.
        auto atFocus = [&](const PclRay& r) {
            const Vec3 o(r.ox, r.oy, r.oz), d(r.dx, r.dy, r.dz);
            const float t = (lens.focusDistance - dot(o - eye, F)) / dot(d, F);
            return o + d * t;
        };
        worst = std::max(worst, double(length(atFocus(a[i]) - atFocus(c[i]))));
        maxOffset = std::max(maxOffset, double(length(Vec3(a[i].ox, a[i].oy, a[i].oz) - eye)));
        EXPECT_EQ(a[i].time, c[i].time);
        EXPECT_GE(a[i].time, 0.0f);
        EXPECT_LT(a[i].time, 1.0f);
        timeSum += a[i].time;
    }
    const double meanTime = timeSum / double(a.size());
    std::printf("[figure] thin lens: worst distance between lens and pinhole rays on the focus plane %.3e m "
                "(focus %.3f m), largest lens offset %.4f (aperture %.4f), mean time %.4f\n",
                worst, lens.focusDistance, maxOffset, lens.apertureRadius, meanTime);
    EXPECT_LT(worst, 1e-5 * lens.focusDistance * 10);
    EXPECT_LE(maxOffset, lens.apertureRadius * (1.0 + 1e-5));
    EXPECT_GT(maxOffset, 0.5 * lens.apertureRadius);
    EXPECT_NEAR(meanTime, 0.5, 4.0 * std::sqrt(1.0 / 12.0 / double(a.size())));
}

TEST(CameraRays, PlanWithoutLensAndTimeSamplesNeither) {
    test::BuiltScene b = test::shippedScene("cornell-box.json", 8, 8);
    RenderPlan plan;  // lens and time sampling off
    const PclCameraParams p = cameraParams(b.scene.camera, plan, 3, 1);
    EXPECT_EQ(p.lensSampling, 0u);
    EXPECT_EQ(p.timeSampling, 0u);
    EXPECT_THROW(cameraParams(b.scene.camera, plan, 3, 0), InternalError);
}

}  // namespace
}  // namespace pcl
