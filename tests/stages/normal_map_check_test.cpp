// The normal-mapped stages, device against twin (kernels/shared/shading_frame.h on both sides),
// on the smooth room with normal maps on the floor (repeated by its transform), the diffuse
// sphere and the glass sphere (test_scenes::normalMappedRoom; generated tangents): trace_photons,
// the whole photon pass, and every eye-pass stage with the films. The same checks and tolerances
// as `photoncl check --stage trace|pass|render`: ≤ 0.1 % divergent photon paths; ≥ 99.9 % of eye
// samples and ≥ 99 % of film pixels within 1e-3 relative.
#include <gtest/gtest.h>

#include <cstdio>

#include "common/smooth_scenes.h"
#include "room_check.h"

namespace pcl {
namespace {

const test::CheckRoom& room() {
    static const test::CheckRoom r("normal-mapped room", test_scenes::normalMappedRoom());
    return r;
}

PhotonCheckReport photonStage(const char* stage, uint32_t photons) {
    return test::checkRoomPhotons(room(), stage, photons, 5);
}

TEST(NormalMapCheck, SceneIsNormalMapped) {
    const NormalMapBuffers& b = room().buffers.normalMaps;
    ASSERT_TRUE(b.mapped());
    ASSERT_EQ(b.triangleTangents.size(), room().geometry.triangleCount());
    EXPECT_EQ(b.maps[size_t(room().scene.meshes[0].material)].texture.width, 16u);
    EXPECT_EQ(b.maps[size_t(room().scene.meshes[7].material)].scale, 0.5f);
}

TEST(NormalMapCheck, TracePhotonsMatchesTheTwin) {
    const PhotonCheckReport r = photonStage("trace", 20000);
    EXPECT_TRUE(r.passed());
    ASSERT_FALSE(r.rows.empty());
    EXPECT_GT(r.rows[0].hostDeposits, 20000u) << "photons should bounce off the spheres and walls";
}

TEST(NormalMapCheck, WholePhotonPassMatchesTheTwin) {
    const PhotonCheckReport r = photonStage("pass", 10000);
    EXPECT_TRUE(r.passed());
}

TEST(NormalMapCheck, EyeStagesAndFilmsMatchTheTwin) { test::expectRoomEyeStagesMatch(room()); }

}  // namespace
}  // namespace pcl
