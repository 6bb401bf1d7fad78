// A scene built in code, device against twin as `photoncl check --stage trace|pass|render` checks
// it (check/photon_stages.h, check/render.h): ≤ 0.1 % divergent photon paths; ≥ 99.9 % of eye
// samples and ≥ 99 % of film pixels within 1e-3 relative. Shared by the stage tests of the
// features that change what a hit reads (textures, shading normals, normal maps).
#pragma once
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <utility>

#include "check/photon_stages.h"
#include "check/render.h"
#include "device_fixture.h"
#include "prep/projection_map.h"

namespace pcl::test {

struct CheckRoom {
    std::string name;  // in the printed tables and figures
    Scene scene;
    SceneGeometry geometry;
    SceneBuffers buffers;
    CheckRoom(std::string n, Scene s)
        : name(std::move(n)), scene(std::move(s)), geometry(SceneGeometry::build(scene)),
          buffers(buildSceneBuffers(scene, geometry)) {
        buildProjectionMaps(scene, geometry, buffers);
    }
};

inline PhotonCheckReport checkRoomPhotons(const CheckRoom& room, const char* stage, uint32_t photons,
                                          uint64_t seed = 5) {
    PhotonCheckOptions o;
    o.photons = photons;
    o.seed = seed;
    const PhotonCheckReport r = checkPhotonStage(testDevice(), room.geometry, room.buffers, stage, o);
    std::printf("%s --stage %s, %u photons per pass\n%s", room.name.c_str(), stage, photons, r.table().c_str());
    return r;
}

// Every eye stage and film at 48×36; `litRows`: final gather and direct light must be mostly
// non-zero (mostly black rows would match trivially).
inline void expectRoomEyeStagesMatch(const CheckRoom& room, bool litRows = true) {
    RenderCheckOptions o;
    o.width = 48;
    o.height = 36;
    const RenderCheckReport r = checkRender(testDevice(), room.scene, o);
    std::printf("%s", r.table().c_str());
    for (const StageComparison& s : r.stages)
        std::printf("[figure] check render %s %s: %.4f %% of %zu match, max rel %.3e\n", room.name.c_str(),
                    s.stage.c_str(), 100.0 * s.fraction(), s.compared, s.maxRelError);
    EXPECT_TRUE(r.passed());
    if (!litRows) return;
    for (const StageComparison& s : r.stages)
        if (s.stage == "final gather" || s.stage == "direct light") {
            EXPECT_GT(s.nonzero, s.compared / 2) << s.stage << ": mostly black rows would match trivially";
        }
}

}  // namespace pcl::test
