// The textured stages, device against twin (kernels/shared/texture.h on both sides), on a room
// with a checkered floor (repeat, scaled and turned) and a gradient wall (mirror/clamp) built in
// code: trace_photons (the textured ρd decides Russian roulette and what a photon carries on),
// the whole photon pass, and every eye-pass stage with the films (eye_paths' textured albedo,
// direct light and the estimates through it, final gather's textured gather hits). The same
// checks and tolerances as `photoncl check --stage trace|pass|render` (check/photon_stages.h,
// check/render.h): ≤ 0.1 % divergent photon paths; ≥ 99.9 % of eye samples and ≥ 99 % of film
// pixels within 1e-3 relative.
#include <gtest/gtest.h>

#include <cstdio>

#include "common/textured_scenes.h"
#include "room_check.h"

namespace pcl {
namespace {

const test::CheckRoom& room() {
    static const test::CheckRoom r("textured room", test_scenes::texturedRoom());
    return r;
}

PhotonCheckReport photonStage(const char* stage, uint32_t photons) {
    return test::checkRoomPhotons(room(), stage, photons, 5);
}

TEST(TextureCheck, SceneIsTextured) {
    ASSERT_TRUE(room().buffers.textures.textured());
    EXPECT_EQ(room().buffers.textures.triangleUvs.size(), room().geometry.triangleCount());
}

TEST(TextureCheck, TracePhotonsMatchesTheTwin) {
    const PhotonCheckReport r = photonStage("trace", 20000);
    EXPECT_TRUE(r.passed());
    ASSERT_FALSE(r.rows.empty());
    EXPECT_GT(r.rows[0].hostDeposits, 20000u) << "photons should bounce off the textured floor and walls";
}

TEST(TextureCheck, WholePhotonPassMatchesTheTwin) {
    const PhotonCheckReport r = photonStage("pass", 10000);
    EXPECT_TRUE(r.passed());
}

TEST(TextureCheck, EyeStagesAndFilmsMatchTheTwin) { test::expectRoomEyeStagesMatch(room()); }

}  // namespace
}  // namespace pcl
