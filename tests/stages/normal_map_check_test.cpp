// The normal-mapped stages, device against twin (kernels/shared/shading_frame.h on both sides),
// on the smooth room with normal maps on the floor (repeated by its transform), the diffuse
// sphere and the glass sphere (test_scenes::normalMappedRoom; generated tangents): trace_photons,
// the whole photon pass, and every eye-pass stage with the films. The same checks and tolerances
// as `photoncl check --stage trace|pass|render`: ≤ 0.1 % divergent photon paths; ≥ 99.9 % of eye
// samples and ≥ 99 % of film pixels within 1e-3 relative.
#include <gtest/gtest.h>

#include <cstdio>

#include "check/photon_stages.h"
#include "check/render.h"
#include "common/smooth_scenes.h"
#include "device_fixture.h"
#include "prep/projection_map.h"

namespace pcl {
namespace {

struct Room {
    Scene scene = test_scenes::normalMappedRoom();
    SceneGeometry geometry = SceneGeometry::build(scene);
    SceneBuffers buffers = buildSceneBuffers(scene, geometry);
    Room() { buildProjectionMaps(scene, geometry, buffers); }
};
const Room& room() {
    static const Room r;
    return r;
}

PhotonCheckReport photonStage(const char* stage, uint32_t photons) {
    PhotonCheckOptions o;
    o.photons = photons;
    o.seed = 5;
    const PhotonCheckReport r = checkPhotonStage(test::testDevice(), room().geometry, room().buffers, stage, o);
    std::printf("normal-mapped room --stage %s, %u photons per pass\n%s", stage, photons, r.table().c_str());
    return r;
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

TEST(NormalMapCheck, EyeStagesAndFilmsMatchTheTwin) {
    RenderCheckOptions o;
    o.width = 48;
    o.height = 36;
    const RenderCheckReport r = checkRender(test::testDevice(), room().scene, o);
    std::printf("%s", r.table().c_str());
    for (const StageComparison& s : r.stages)
        std::printf("[figure] check render normal-mapped room %s: %.4f %% of %zu match, max rel %.3e\n",
                    s.stage.c_str(), 100.0 * s.fraction(), s.compared, s.maxRelError);
    EXPECT_TRUE(r.passed());
    for (const StageComparison& s : r.stages)
        if (s.stage == "final gather" || s.stage == "direct light") {
            EXPECT_GT(s.nonzero, s.compared / 2) << s.stage << ": mostly black rows would match trivially";
        }
}

}  // namespace
}  // namespace pcl
