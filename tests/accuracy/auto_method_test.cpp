// render --method auto's pilot (render/auto_method.h) at 64 wide (it renders the whole 64²
// image): cornell-spheres, whose caustic under the glass ball the path tracer finds by chance,
// must pick an fg split, and motion-dof (lens, shutter, a lamp seen in specular balls), where the
// path tracer wins at equal time, the path tracer. Measured over seeds 0-3: fg 6×6 × 2 with
// relMSE × seconds 1.6-2× below the path tracer's, and the path tracer 1.6-3× below fg 6×6 × 2.
// (With two path-traced pilot renders instead of six, one firefly tripled the path tracer's
// variance and motion-dof chose fg for one seed of four.) Every candidate's product is finite and
// positive and the chosen one the lowest.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "accuracy/accuracy_common.h"
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
}

TEST(AutoMethod, TriesTheCheapSplitWhenEyeSamplesReadTheCausticMap) {
    const AutoMethodChoice c = pilot("cornell-spheres.json", "map");
    EXPECT_EQ(c.best().request.method, "fg");
    EXPECT_EQ(c.candidates.size(), 3u) << "a caustic map read at eye hits: two fg splits and the path tracer";
}

TEST(AutoMethod, PicksThePathTracerForMotionDof) { EXPECT_EQ(pilot("motion-dof.json").best().request.method, "path"); }

// Without --time the winner spends what fg's default passes would take, as the pilot predicts:
// fg's pass of 0.5 s × 10 default passes at 256² = 5 s, so the path tracer at 2 ms a sample per
// pixel gets 2500 samples, an fg split at 1.25 s a pass 4 passes, fg itself its 10.
TEST(AutoMethod, WithoutATimeBudgetTheWinnerGetsFgsDefaultTime) {
    AutoMethodChoice c;
    c.candidates = {{"fg", {}, 1.0, 0.5}, {"fg 6x6x2", {}, 1.0, 1.25}, {"path", {}, 1.0, 0.002}};
    EXPECT_DOUBLE_EQ(c.fgBudgetSeconds(256, 256), 5.0);
    const uint32_t expected[] = {10, 4, 2500};
    for (size_t i = 0; i < 3; ++i) {
        c.chosen = i;
        EXPECT_EQ(c.unitsWithoutBudget(256, 256), expected[i]) << c.best().name;
    }
    c.candidates.back().unitSeconds = 1e-12;  // never more than 2^20 samples per pixel
    EXPECT_EQ(c.unitsWithoutBudget(256, 256), 1u << 20);
}
