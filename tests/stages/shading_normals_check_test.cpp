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

#include "check/photon_stages.h"
#include "check/render.h"
#include "common/smooth_scenes.h"
#include "device_fixture.h"
#include "prep/projection_map.h"

namespace pcl {
namespace {

struct Room {
    Scene scene = test_scenes::smoothRoom();
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
    std::printf("smooth room --stage %s, %u photons per pass\n%s", stage, photons, r.table().c_str());
    return r;
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

TEST(ShadingNormalsCheck, EyeStagesAndFilmsMatchTheTwin) {
    RenderCheckOptions o;
    o.width = 48;
    o.height = 36;
    const RenderCheckReport r = checkRender(test::testDevice(), room().scene, o);
    std::printf("%s", r.table().c_str());
    for (const StageComparison& s : r.stages)
        std::printf("[figure] check render smooth room %s: %.4f %% of %zu match, max rel %.3e\n", s.stage.c_str(),
                    100.0 * s.fraction(), s.compared, s.maxRelError);
    EXPECT_TRUE(r.passed());
    for (const StageComparison& s : r.stages)
        if (s.stage == "final gather" || s.stage == "direct light") {
            EXPECT_GT(s.nonzero, s.compared / 2) << s.stage << ": mostly black rows would match trivially";
        }
}

}  // namespace
}  // namespace pcl
