// Caustic connections (kernels/connect_caustics.cl) against the twin (reference/connect_caustics),
// the kernels' camera connection (shared/camera.h) against the reference camera's, and the eye
// estimate's minDepth, which leaves the directly seen hits to the connections.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "eye_test_scenes.h"
#include "pipeline/connect_caustics.h"
#include "pipeline/device_scene.h"
#include "pipeline/eye_estimate.h"
#include "prep/photon_allocation.h"
#include "reference/camera.h"
#include "reference/connect_caustics.h"
#include "reference/emit.h"
#include "reference/eye_estimate.h"
#include "reference/photon_pass.h"
#include "shared/camera.h"

namespace pcl {
namespace {

Camera testCamera(bool thinLens) {
    Camera c;
    c.model = thinLens ? CameraModel::ThinLens : CameraModel::Pinhole;
    c.position = Vec3(0.3f, 0.4f, -2.0f);
    c.lookAt = Vec3(0.1f, 0.2f, 0.5f);
    c.vfovDegrees = 35.0f;
    c.width = 64;
    c.height = 48;
    c.apertureRadius = thinLens ? 0.08f : 0.0f;
    c.focusDistance = 2.2f;
    return c;
}

// The kernels' camera_connect and RayCamera::connect (written apart) agree on the pixel, the lens
// point and the importance of points all around the camera, pinhole and thin lens; and a camera
// ray through the pixel the connection names lands near the point (the inverse of camera.cl).
TEST(SharedCamera, ConnectAgreesWithTheReferenceCamera) {
    for (bool thinLens : {false, true}) {
        const Camera cam = testCamera(thinLens);
        const PclCameraParams cp = cameraParams(cam, thinLens, false, 7, 1);
        const RayCamera rc(cam);
        std::mt19937 rng(11);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        int both = 0, neither = 0, disagree = 0;
        float maxImportanceRel = 0.0f, maxLens = 0.0f;
        for (int i = 0; i < 20000; ++i) {
            const Vec3 p(-3.0f + 6.0f * u(rng), -3.0f + 6.0f * u(rng), -4.0f + 8.0f * u(rng));
            const float lu = u(rng), lv = u(rng);
            uint32_t pixel = 0;
            PclV3 lens;
            float importance = 0.0f;
            const bool k = camera_connect(&cp, sampling_v3(p.x, p.y, p.z), lu, lv, &pixel, &lens, &importance) != 0;
            CameraConnection c;
            const bool r = rc.connect(p, lu, lv, c);
            if (!k && !r) {
                ++neither;
                continue;
            }
            if (k != r || pixel != uint32_t(c.y * cam.width + c.x)) {
                ++disagree;  // a point on a pixel's edge may round either way
                continue;
            }
            ++both;
            maxImportanceRel = std::max(maxImportanceRel, std::abs(importance - c.importance) / c.importance);
            maxLens = std::max(maxLens, length(Vec3(lens.x, lens.y, lens.z) - c.lensPoint));
        }
        std::printf("[figure] camera connect (%s): %d agree, %d outside both, %d disagree; max importance rel "
                    "%.2e, max lens point %.2e\n",
                    thinLens ? "thin lens" : "pinhole", both, neither, disagree, maxImportanceRel, maxLens);
        EXPECT_GT(both, 2000);
        EXPECT_GT(neither, 2000);
        EXPECT_LE(disagree, 10);
        EXPECT_LT(maxImportanceRel, 1e-4f);
        EXPECT_LT(maxLens, 1e-5f);
    }
}

// The caustic photons of cornell-spheres-point (a point lamp above a mirror and a glass ball):
// every record's splat on the device and in the twin, the same pixel and value to 1e-4 (rays
// offset differently near an occluder may disagree on a few: at most 0.2 %).
TEST(ConnectCaustics, DeviceMatchesTheTwin) {
    for (bool thinLens : {false, true}) {
        test::BuiltScene b = test::shippedScene("cornell-spheres-point.json", 64, 48);
        if (thinLens) {
            b.scene.camera.model = CameraModel::ThinLens;
            b.scene.camera.apertureRadius = 0.02f;
            b.scene.camera.focusDistance = 0.9f;
        }
        ReferencePhotonPassSettings ps;
        ps.seed = 3;
        ps.causticPhotons = 30000;
        const std::vector<PclPhoton> caustic = referencePhotonMap(b.buffers, b.geometry, ps, PCL_PASS_CAUSTIC);
        ASSERT_GT(caustic.size(), 10000u);
        const uint64_t seed = eyePassSeed(3, 1);
        const PclCameraParams cp = cameraParams(b.scene.camera, thinLens, false, seed, 1);
        const PclConnectParams params = connectParams(b.geometry, b.buffers, uint32_t(caustic.size()), seed);
        DeviceScene scene(test::testDevice(), b.geometry, b.buffers);
        const std::vector<PclSplat> d = connectCaustics(test::testDevice(), scene, params, cp, caustic);
        const std::vector<PclSplat> t = referenceConnectCaustics(b.scene, b.geometry, params, cp, caustic);
        ASSERT_EQ(d.size(), t.size());
        size_t splats = 0, differ = 0;
        float maxRel = 0.0f;
        for (size_t i = 0; i < d.size(); ++i) {
            if (d[i].pixel != t[i].pixel) {
                ++differ;
                continue;
            }
            if (d[i].pixel == PCL_NO_SPLAT) continue;
            const float rel = std::max({std::abs(d[i].r - t[i].r) / std::max(t[i].r, 1e-30f),
                                        std::abs(d[i].g - t[i].g) / std::max(t[i].g, 1e-30f),
                                        std::abs(d[i].b - t[i].b) / std::max(t[i].b, 1e-30f)});
            if (!(rel < 1e-4f)) {
                ++differ;
                continue;
            }
            ++splats;
            maxRel = std::max(maxRel, rel);
            EXPECT_TRUE(std::isfinite(d[i].r) && std::isfinite(d[i].g) && std::isfinite(d[i].b));
        }
        std::printf("[figure] connect caustics cornell-spheres-point 64x48 (%s): %zu records, %zu splats agree "
                    "(max rel %.2e), %zu differ\n",
                    thinLens ? "thin lens" : "pinhole", d.size(), splats, maxRel, differ);
        EXPECT_LE(differ, d.size() / 500);
        EXPECT_GT(splats, d.size() / 4);  // the caustic under the glass ball faces the camera
    }
}

// minDepth: records with fewer specular bounces before their hit get an empty query (the
// connections light them), the others the usual one, on the device and in the twin.
TEST(ConnectCaustics, EyeEstimateLeavesDirectlySeenHitsToTheConnections) {
    std::vector<PclEyeHit> hits;
    for (uint32_t i = 0; i < 4; ++i) {
        PclEyeHit h = test::handMadeHit(Vec3(0.1f * i, 0.0f, 0.0f), Vec3(0, 1, 0), 0.5f, i, 0);
        h.depth = i % 2;
        hits.push_back(h);
    }
    PclEyeEstimateParams p{};
    p.sampleCount = uint32_t(hits.size());
    p.k = 10;
    p.maxRadius2 = 0.25f;
    p.minDepth = 1;
    const std::vector<PclEstimateQuery> q = referenceEyeEstimateQueries(hits, p, {});
    for (size_t i = 0; i < hits.size(); ++i) EXPECT_EQ(q[i].maxRadius2, hits[i].depth >= 1 ? 0.25f : 0.0f) << i;
    Device& dev = test::testDevice();
    const cl::Buffer hitBuf = dev.upload(hits, CL_MEM_READ_ONLY, "test: eye hits");
    cl::Buffer queries = dev.allocate<PclEstimateQuery>(hits.size(), CL_MEM_READ_WRITE, "test: queries");
    const cl::Buffer prims = dev.upload(std::vector<PclPrimInfo>(1), CL_MEM_READ_ONLY, "test: primitives (unread)");
    eyeEstimateQueries(dev, p, hitBuf, prims, queries);
    const std::vector<PclEstimateQuery> dq = dev.download<PclEstimateQuery>(queries, hits.size());
    ASSERT_EQ(dq.size(), q.size());
    for (size_t i = 0; i < q.size(); ++i) EXPECT_EQ(dq[i].maxRadius2, q[i].maxRadius2) << i;
}

// The shutter time of a record (prep/photon_allocation.h, photonEmissionTime) is the one emit gave
// its path: motion-dof's caustic and global photons, against the twin's emit, bit for bit.
TEST(ConnectCaustics, RecordTimesAreTheTimesEmitGaveTheirPaths) {
    test::BuiltScene b = test::shippedScene("motion-dof.json", 64, 48);
    ASSERT_TRUE(b.buffers.hasMotion);
    for (uint32_t kind : {uint32_t(PCL_PASS_GLOBAL), uint32_t(PCL_PASS_CAUSTIC)}) {
        const std::vector<uint32_t> first = referenceLightFirstPhoton(b.buffers, kind, 4000);
        const PclPhotonParams params = referencePhotonParams(b.buffers, b.geometry, 77, kind, 1000, 3000, 16);
        const std::vector<PclPhotonRay> rays = emitPhotonsReference(b.buffers, first, params, 1);
        size_t differ = 0;
        float lo = 1.0f, hi = 0.0f;
        for (uint32_t i = 0; i < rays.size(); ++i) {
            const float t = photonEmissionTime(params, params.firstPhoton + i);
            differ += t != rays[i].time;
            lo = std::min(lo, t);
            hi = std::max(hi, t);
        }
        EXPECT_EQ(differ, 0u) << (kind == PCL_PASS_CAUSTIC ? "caustic" : "global");
        EXPECT_LT(lo, 0.01f);  // spread over the shutter
        EXPECT_GT(hi, 0.99f);
    }
}

// In a scene that moves each record is connected at its own shutter time: motion-dof's global
// photons (more of them land on the moving ball than caustic ones; the kernel reads any records)
// with their times, device against twin as above; and the records on the moving ball, which
// only their own instant finds again, splat about as often as the rest with their times and
// hardly at all when every connection is traced at time 0.
TEST(ConnectCaustics, ConnectionsInAMovingSceneAreTracedAtEachPhotonsTime) {
    test::BuiltScene b = test::shippedScene("motion-dof.json", 64, 48);
    const Sphere* moving = nullptr;
    for (const Sphere& sp : b.scene.spheres)
        if (length(sp.motion) > 0.0f) moving = &sp;
    ASSERT_NE(moving, nullptr);
    ReferencePhotonPassSettings ps;
    ps.seed = 3;
    ps.globalPhotons = 80000;
    std::vector<uint32_t> counts;
    std::vector<PclPhoton> records = referencePhotonMap(b.buffers, b.geometry, ps, PCL_PASS_GLOBAL, nullptr, &counts);
    std::vector<float> times;
    appendRecordTimes(referencePhotonParams(b.buffers, b.geometry, referencePhotonPassSeed(ps.seed, ps.pass),
                                            PCL_PASS_GLOBAL, 0, 0, 16),
                      counts, times);
    ASSERT_EQ(times.size(), records.size());
    // The global map keeps the moving ball's photons where the ball sits at shutter open
    // (kernels/shared/shutter_open.h); a caustic map, which these records stand in for, keeps
    // them where they landed, at their own time: put them back there.
    std::vector<bool> onBall(records.size());
    size_t ballRecords = 0;
    for (size_t i = 0; i < records.size(); ++i) {
        PclPhoton& ph = records[i];
        const float d = length(Vec3(ph.x, ph.y, ph.z) - moving->centre);
        onBall[i] = std::abs(d - moving->radius) < 1e-3f;
        ballRecords += onBall[i];
        if (!onBall[i]) continue;
        const Vec3 landed = Vec3(ph.x, ph.y, ph.z) + moving->motion * times[i];
        ph.x = landed.x, ph.y = landed.y, ph.z = landed.z;
    }
    ASSERT_GT(ballRecords, 200u) << "the ball's photons at shutter open";

    const uint64_t seed = eyePassSeed(3, 1);
    DeviceScene scene(test::testDevice(), b.geometry, b.buffers);
    size_t ballSplats[2] = {0, 0}, otherSplats[2] = {0, 0};
    for (bool withTimes : {false, true}) {
        // (A camera that samples time refuses records without times; the connection reads none.)
        const PclCameraParams cp = cameraParams(b.scene.camera, true, withTimes, seed, 1);
        const PclConnectParams params = connectParams(b.geometry, b.buffers, uint32_t(records.size()), seed, withTimes);
        const std::vector<float> t = withTimes ? times : std::vector<float>{};
        const std::vector<PclSplat> d = connectCaustics(test::testDevice(), scene, params, cp, records, t);
        const std::vector<PclSplat> r = referenceConnectCaustics(b.scene, b.geometry, params, cp, records, t);
        ASSERT_EQ(d.size(), r.size());
        size_t differ = 0;
        for (size_t i = 0; i < d.size(); ++i) {
            const float rel =
                std::max({std::abs(d[i].r - r[i].r), std::abs(d[i].g - r[i].g), std::abs(d[i].b - r[i].b)}) /
                std::max({r[i].r, r[i].g, r[i].b, 1e-30f});
            if (d[i].pixel != r[i].pixel || !(rel < 1e-4f)) ++differ;
            if (d[i].pixel == PCL_NO_SPLAT) continue;
            (onBall[i] ? ballSplats : otherSplats)[withTimes]++;
        }
        std::printf("[figure] motion-dof global records %s times: %zu records (%zu on the moving ball), splats %zu "
                    "on the ball / %zu elsewhere, %zu differ from the twin\n",
                    withTimes ? "with" : "without", d.size(), ballRecords, ballSplats[withTimes],
                    otherSplats[withTimes], differ);
        EXPECT_LE(differ, d.size() / 500);
    }
    const double ballRate = double(ballSplats[1]) / double(ballRecords);
    const double otherRate = double(otherSplats[1]) / double(records.size() - ballRecords);
    EXPECT_GT(ballRate, 0.5 * otherRate) << "records on the moving ball, connected at their time";
    EXPECT_LT(ballSplats[0], ballSplats[1] / 4) << "at time 0 the ball is elsewhere for most of them";
}

}  // namespace
}  // namespace pcl
