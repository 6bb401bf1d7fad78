// render --method auto's pilot (render/auto_method.h) at 64 wide (it renders the whole 64²
// image): cornell-spheres, whose caustic under the glass ball the path tracer finds by chance,
// must pick an fg split, and motion-dof (lens, shutter, a lamp seen in specular balls) is a close
// call between fg and the path tracer. Measured over seeds 0-3 before the caustic
// fireflies were counted: fg 6×6 × 2 with relMSE × seconds 1.6-2× below the path tracer's, and
// the path tracer 1.6-3× below fg 6×6 × 2 (with them, seed 1: 4.6× and 1.3×). (With two
// path-traced pilot renders instead of six, one firefly tripled the path tracer's variance and
// motion-dof chose fg for one seed of four.) Every candidate's product is finite and positive
// and the chosen one the lowest. fg's gather rays follow the indirect part's share of its variance
// and time (gatherRaysForTheIndirectShare).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "accuracy/accuracy_common.h"
#include "core/math.h"
#include "prep/prepared_scene.h"
#include "render/auto_method.h"
#include "stages/device_fixture.h"

using namespace pcl;

namespace {

AutoMethodChoice pilot(const std::string& name, const std::string& caustics = "") {
    const Scene scene = accuracy::loadSceneAt(name, 64, 64);
    const PreparedScene prepared = prepareScene(scene);
    RenderRequest request;
    request.seed = 1;
    request.caustics = caustics;
    const AutoMethodChoice c = chooseRenderMethod(test::testDevice(), scene, prepared, request);
    std::printf("[figure] %s at 64 wide: %s", name.c_str(), c.log().c_str());
    for (const AutoCandidate& k : c.candidates) {
        EXPECT_TRUE(std::isfinite(k.errorSeconds) && k.errorSeconds > 0) << name << " " << k.name;
        EXPECT_LE(c.best().errorSeconds, k.errorSeconds) << name << " " << k.name;
    }
    return c;
}

}  // namespace

// By default fg connects caustic photons to the camera and its eye samples are already the cheap
// 6×6 × 2 split: one fg candidate. With --caustics map the eye samples read the caustic map, and
// the pilot also tries the 6×6 split.
TEST(AutoMethod, PicksFinalGatheringForACausticScene) {
    const AutoMethodChoice c = pilot("cornell-spheres.json");
    EXPECT_EQ(c.best().request.method, "fg");
    EXPECT_EQ(c.candidates.size(), 2u) << "caustic connections: fg (already 6x6x2) and the path tracer";
    // The indirect part holds about 3/4 of fg's variance and 1/7 of its time: the formula asks for
    // about 4x the default 2 gather rays, capped at twice.
    EXPECT_EQ(c.best().request.gatherRays, 4u) << c.best().tuned;
}

TEST(AutoMethod, TriesTheCheapSplitWhenEyeSamplesReadTheCausticMap) {
    const AutoMethodChoice c = pilot("cornell-spheres.json", "map");
    EXPECT_EQ(c.best().request.method, "fg");
    EXPECT_EQ(c.candidates.size(), 3u) << "a caustic map read at eye hits: two fg splits and the path tracer";
}

// motion-dof is a close call, as equal time at 256² found (the pilot picked the path tracer at
// 10 s and fg at 30 and 60 s; fg won RMSE and lost relMSE). At 64 wide the two figures came within
// 0.87-1.43x of each other over 14 runs on 2026-12-03, which side wins following the machine's
// timings, so the test holds them close instead of naming a winner (it named the path tracer and
// failed 3 runs of 14 on the idle machine).
TEST(AutoMethod, MotionDofIsACloseCallBetweenFgAndThePathTracer) {
    const AutoMethodChoice c = pilot("motion-dof.json");
    ASSERT_EQ(c.candidates.size(), 2u);
    const double ratio = c.candidates.front().errorSeconds / c.candidates.back().errorSeconds;
    EXPECT_GT(ratio, 0.5) << c.log();
    EXPECT_LT(ratio, 2.0) << c.log();
}

// Without --time the winner spends what fg's default passes would take, as the pilot predicts:
// fg's pass of 0.5 s × 10 default passes at 256² = 5 s, so the path tracer at 2 ms a sample per
// pixel gets 2500 samples, an fg split at 1.25 s a pass 4 passes, fg itself its 10.
TEST(AutoMethod, WithoutATimeBudgetTheWinnerGetsFgsDefaultTime) {
    AutoMethodChoice c;
    c.candidates = {{"fg", {}, 1.0, 0.5, 0, {}}, {"fg 6x6x2", {}, 1.0, 1.25, 0, {}}, {"path", {}, 1.0, 0.002, 0, {}}};
    c.fgDefaultPassSeconds = 0.5;
    EXPECT_DOUBLE_EQ(c.fgBudgetSeconds(256, 256), 5.0);
    const uint32_t expected[] = {10, 4, 2500};
    for (size_t i = 0; i < 3; ++i) {
        c.chosen = i;
        EXPECT_EQ(c.unitsWithoutBudget(256, 256), expected[i]) << c.best().name;
    }
    c.candidates.back().unitSeconds = 1e-12;  // never more than 2^20 samples per pixel
    EXPECT_EQ(c.unitsWithoutBudget(256, 256), 1u << 20);
}

// The path tracer's caustic fireflies (causticFireflyVariance): a caustic sample found with
// probability p is worth ρ L_e, so its variance is L_c ρ L_e. 0.1 × 0.5 × (10, 20, 40) over a
// mean of 1 (relMSE's ε 0.01 in the denominator): (0.5 + 1 + 2) / 3 / 1.01.
TEST(AutoMethod, CausticFireflyVarianceIsCausticTimesAlbedoTimesEmitterRadiance) {
    Image caustic(2, 1), albedo(2, 1), mean(2, 1);
    for (int x = 0; x < 2; ++x) {
        caustic.set(x, 0, Vec3(0.1f));
        albedo.set(x, 0, Vec3(0.5f));
        mean.set(x, 0, Vec3(1.0f));
    }
    EXPECT_NEAR(causticFireflyVariance(caustic, albedo, mean, Vec3(10, 20, 40)), 3.5 / 3.0 / 1.01, 1e-5);
    caustic.set(1, 0, Vec3(0.0f));  // a pixel without caustic light adds nothing
    EXPECT_NEAR(causticFireflyVariance(caustic, albedo, mean, Vec3(10, 20, 40)), 0.5 * 3.5 / 3.0 / 1.01, 1e-5);
}

// The emitters' radiance as caustic light weights it: the constant sky's own radiance
// (sky-spheres), the area light's Φ / (π A) (cornell-spheres: the same in every channel ratio as
// its power), nothing for a point light (the path tracer's light tracer finds its caustics), and
// for the courtyard's sky, whose sun texel (5943) makes almost all its caustic light, between
// the sky's mean radiance and the sun's.
TEST(AutoMethod, CausticEmitterRadianceWeighsEmittersByTheirCausticLight) {
    auto radiance = [](const std::string& name) {
        const Scene scene = accuracy::loadSceneAt(name, 32, 32);
        return causticEmitterRadiance(scene, prepareScene(scene).buffers);
    };
    const Vec3 sky = radiance("sky-spheres.json");
    EXPECT_NEAR(sky.x, 0.6, 1e-5);
    EXPECT_NEAR(sky.y, 0.8, 1e-5);
    EXPECT_NEAR(sky.z, 1.0, 1e-5);
    const Vec3 point = radiance("cornell-spheres-point.json");
    EXPECT_EQ(point.x + point.y + point.z, 0.0f);
    const Scene box = accuracy::loadSceneAt("cornell-spheres.json", 32, 32);
    const PreparedScene boxPrepared = prepareScene(box);
    double power = 0, area = 0;
    for (const PclLight& l : boxPrepared.buffers.lights)
        if (l.type == PCL_LIGHT_TRIANGLE) {
            power += l.power[1];
            area += l.area;
        }
    ASSERT_GT(area, 0.0);
    EXPECT_NEAR(causticEmitterRadiance(box, boxPrepared.buffers).y, power / (kPiD * area), 1e-3 * power / area);
    const Vec3 sun = radiance("courtyard/courtyard.json");
    std::printf("[figure] courtyard: caustic emitter radiance %.1f %.1f %.1f\n", sun.x, sun.y, sun.z);
    EXPECT_GT(sun.y, 1000.0f) << "the sun texel's light dominates";
    EXPECT_LT(sun.y, 5943.0f * 1.01f);
}

// The courtyard's sun caustic through the glass ball: a 16-spp pilot rarely meets its fireflies
// (at 10 s the pilot chose the path tracer and lost, RMSE 0.443 against fg's ~0.06). With the
// fireflies counted from fg's pilot, fg wins the pilot and most of the path tracer's variance is theirs.
TEST(AutoMethod, CountsThePathTracersCausticFirefliesOnTheCourtyard) {
    const AutoMethodChoice c = pilot("courtyard/courtyard.json");
    EXPECT_EQ(c.best().request.method, "fg");
    EXPECT_GT(c.candidates.back().fireflyShare, 0.5);
}

// fg's gather rays by the indirect part's shares: with 80 % of the variance and 20 % of the time
// in the indirect part, g/g0 = sqrt(0.8 · 0.8 / (0.2 · 0.2)) = 4, where the predicted error ×
// time (0.2 + 0.8/4)(0.8 + 0.2 · 4) = 0.64 is the least (1 at g0); the cap, and no change where
// a share is missing.
TEST(AutoMethod, GatherRaysFollowTheIndirectPartsShareOfVarianceAndTime) {
    EXPECT_EQ(gatherRaysForTheIndirectShare(2, 1.0, 0.8, 1.0, 0.2, 16), 8u);
    EXPECT_EQ(gatherRaysForTheIndirectShare(2, 1.0, 0.8, 1.0, 0.2, 4), 4u);
    EXPECT_EQ(gatherRaysForTheIndirectShare(8, 1.0, 0.2, 1.0, 0.8, 16), 2u);  // a cheap indirect part: fewer
    EXPECT_NEAR(predictedErrorSeconds(2, 8, 1.0, 0.8, 1.0, 0.2), 0.64, 1e-12);
    EXPECT_NEAR(predictedErrorSeconds(2, 2, 1.0, 0.8, 1.0, 0.2), 1.0, 1e-12);
    for (uint32_t g : {6u, 7u, 9u, 10u})
        EXPECT_GT(predictedErrorSeconds(2, g, 1.0, 0.8, 1.0, 0.2), predictedErrorSeconds(2, 8, 1.0, 0.8, 1.0, 0.2));
    EXPECT_EQ(gatherRaysForTheIndirectShare(2, 1.0, 0.0, 1.0, 0.2, 16), 2u);  // no indirect variance
    EXPECT_EQ(gatherRaysForTheIndirectShare(2, 1.0, 0.8, 1.0, 0.0, 16), 2u);  // no indirect time
    EXPECT_EQ(gatherRaysForTheIndirectShare(2, 1.0, 1.0, 1.0, 0.2, 16), 2u);  // nothing else to weigh

    // partVariance: a part that differs from the whole by a constant carries all its variance.
    Image a(1, 1), b(1, 1), pa(1, 1), pb(1, 1);
    a.set(0, 0, Vec3(1.0f, 2.0f, 3.0f));
    b.set(0, 0, Vec3(3.0f, 2.0f, 1.0f));
    pa.set(0, 0, Vec3(0.5f, 1.5f, 2.5f));
    pb.set(0, 0, Vec3(2.5f, 1.5f, 0.5f));
    // Per channel: sample variance over (mean² + 0.01) with the whole image's mean 2: (2, 0, 2) / 4.01.
    EXPECT_NEAR(partVariance({pa, pb}, {a, b}), (2.0 + 0.0 + 2.0) / 3.0 / 4.01, 1e-6);
}
