// Textured specular lobes, device against twin (kernels/shared/texture.h on both sides): a room
// with a mirror panel whose ρs is a checker, a glossy panel with textured ρs and exponent, and a
// glTF metallic-roughness panel (test_scenes::specularTexturedRoom). The stages that read ρs or
// the exponent at a hit: trace_photons (Russian roulette between the lobes, the glossy bounce),
// the whole photon pass, and every eye-pass stage with the films (eye_paths' lobe choice and
// glossy next-event estimation, final gather's gather hits). The same checks and tolerances as
// `photoncl check --stage trace|pass|render` (check/photon_stages.h, check/render.h): ≤ 0.1 %
// divergent photon paths; ≥ 99.9 % of eye samples and ≥ 99 % of film pixels within 1e-3
// relative.
#include <gtest/gtest.h>

#include <cstdio>

#include "common/textured_scenes.h"
#include "room_check.h"

namespace pcl {
namespace {

const test::CheckRoom& room() {
    static const test::CheckRoom r("specular textured room", test_scenes::specularTexturedRoom());
    return r;
}

PhotonCheckReport photonStage(const char* stage, uint32_t photons) {
    return test::checkRoomPhotons(room(), stage, photons, 11);
}

TEST(SpecularTextureCheck, SlotsArePacked) {
    const auto& t = room().buffers.textures.materialTextures;
    int rhoS = 0, exponent = 0, metallicRoughness = 0;
    for (const PclMaterialTextures& m : t) {
        rhoS += m.slot[PCL_TEXTURE_RHO_S].width > 0;
        exponent += m.slot[PCL_TEXTURE_EXPONENT].width > 0;
        metallicRoughness += m.mapping == PCL_TEXTURE_MAP_METALLIC_ROUGHNESS;
    }
    EXPECT_EQ(rhoS, 2);
    EXPECT_EQ(exponent, 2);
    EXPECT_EQ(metallicRoughness, 1);
}

TEST(SpecularTextureCheck, TracePhotonsMatchesTheTwin) {
    const PhotonCheckReport r = photonStage("trace", 20000);
    EXPECT_TRUE(r.passed());
}

TEST(SpecularTextureCheck, WholePhotonPassMatchesTheTwin) {
    const PhotonCheckReport r = photonStage("pass", 10000);
    EXPECT_TRUE(r.passed());
}

TEST(SpecularTextureCheck, EyeStagesAndFilmsMatchTheTwin) { test::expectRoomEyeStagesMatch(room(), false); }

}  // namespace
}  // namespace pcl
