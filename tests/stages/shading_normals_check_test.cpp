// The smooth-shaded stages, device against twin (kernels/shared/shading_frame.h on both sides),
// on a room with three smooth low-poly spheres (diffuse, glass, glossy) built in code:
// trace_photons (the scattering frame, the geometric side tests and the adjoint factor), the
// whole photon pass, and every eye-pass stage with the films (eye_paths' shading normal, direct
// light's cosines, final gather's gather-ray frame and its specular gather hits). The same checks
// and tolerances as `photoncl check --stage trace|pass|render` (check/photon_stages.h,
// check/render.h): ≤ 0.1 % divergent photon paths; ≥ 99.9 % of eye samples and ≥ 99 % of film
// pixels within 1e-3 relative.
#include <gtest/gtest.h>

#include <cstdio>

#include "common/smooth_scenes.h"
#include "room_check.h"

namespace pcl {
namespace {

const test::CheckRoom& room() {
    static const test::CheckRoom r("smooth room", test_scenes::smoothRoom());
    return r;
}

PhotonCheckReport photonStage(const char* stage, uint32_t photons) {
    return test::checkRoomPhotons(room(), stage, photons, 5);
}

TEST(ShadingNormalsCheck, SceneIsSmooth) {
    ASSERT_EQ(room().buffers.triangleNormals.size(), room().geometry.triangleCount());
    // The room's quads are flat (zeros), the spheres' triangles are not.
    EXPECT_EQ(room().buffers.triangleNormals[0].n[1], 0.0f);
    EXPECT_NE(room().buffers.triangleNormals.back().n[1], 0.0f);
}

TEST(ShadingNormalsCheck, TracePhotonsMatchesTheTwin) {
    const PhotonCheckReport r = photonStage("trace", 20000);
    EXPECT_TRUE(r.passed());
    ASSERT_FALSE(r.rows.empty());
    EXPECT_GT(r.rows[0].hostDeposits, 20000u) << "photons should bounce off the spheres and walls";
}

TEST(ShadingNormalsCheck, WholePhotonPassMatchesTheTwin) {
    const PhotonCheckReport r = photonStage("pass", 10000);
    EXPECT_TRUE(r.passed());
}

TEST(ShadingNormalsCheck, EyeStagesAndFilmsMatchTheTwin) { test::expectRoomEyeStagesMatch(room()); }

}  // namespace
}  // namespace pcl
