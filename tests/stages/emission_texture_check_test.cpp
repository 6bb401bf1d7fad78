// Emission textures in the photon and eye passes, device against twin, on the textured room with
// a checker-textured lamp (test_scenes::emissiveTexturedRoom):
//   - emit: every photon's power bit for bit equal to the twin's (the lamp's photons carry
//     π A L(x) / n of their own point, L(x) = factor × the texel there; origins and directions
//     within `check --stage emit`'s tolerances: the point light's warps use sin/cos), and
//     `check --stage emit` passes with no mismatch; 1/8 of the lamp's photons carry no green
//     (where bilinear filtering reads only the dark squares' texels, G = 0: the middle quarter
//     of each dark 2 × 2 square);
//   - the lamp's photons carry π ∫ L dA in all: for a quad mapped once onto a clamped texture
//     the integral of the bilinear filter is the mean texel (each texel weighs 1/(W H)), so here
//     (repeat, scaled by 2: the checker twice each way, the same mean) ∫ L dA = A × factor ×
//     mean texel; 1 000 000 photons, the lamp's share ~67 000 (by power, beside the point
//     light), the checker's spread gives a relative standard error of ~0.35 %: within 2 % (6σ);
//   - the whole photon pass and every eye stage and film match the twin with the usual
//     tolerances (stages/room_check.h: direct light's samples of the lamp, the gather rays
//     that hit it, the glossy panel's light samples).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "check/on_device.h"
#include "common/textured_scenes.h"
#include "core/math.h"
#include "prep/photon_allocation.h"
#include "reference/emit.h"
#include "room_check.h"

namespace pcl {
namespace {

const test::CheckRoom& room() {
    static const test::CheckRoom r("emissive textured room", test_scenes::emissiveTexturedRoom());
    return r;
}

// The lamp's light entries: the triangles of the last mesh.
bool isLamp(const test::CheckRoom& r, const PclLight& L) {
    return L.type == PCL_LIGHT_TRIANGLE && L.prim + 2 >= r.geometry.triangleCount();
}

TEST(EmissionTextureCheck, SceneHasATexturedLamp) {
    const test::CheckRoom& r = room();
    const Material& lamp = r.scene.materials[size_t(r.scene.meshes.back().material)];
    ASSERT_GE(lamp.emissionTexture, 0);
    const uint32_t mat = uint32_t(r.scene.meshes.back().material);
    EXPECT_GT(r.buffers.textures.materialTextures[mat].slot[PCL_TEXTURE_EMISSION].width, 0u);
    int lamps = 0;
    for (const PclLight& L : r.buffers.lights) lamps += isLamp(r, L);
    EXPECT_EQ(lamps, 2);
}

TEST(EmissionTextureCheck, EmitMatchesTheTwinBitForBitAndCarriesPiTimesTheIntegralOfL) {
    const test::CheckRoom& r = room();
    constexpr uint32_t kPhotons = 1000000;
    const std::vector<uint32_t> first = lightFirstPhoton(r.buffers, kPhotons, PCL_PASS_GLOBAL);
    const PclPhotonParams params = makePhotonParams(r.geometry, r.buffers, PCL_PASS_GLOBAL, 11, 8, 0, first.back());
    const std::vector<PclPhotonRay> dev = emitOnDevice(test::testDevice(), r.geometry, r.buffers, first, params);
    const std::vector<PclPhotonRay> twin = emitPhotonsReference(r.buffers, first, params);
    ASSERT_EQ(dev.size(), twin.size());
    double flux[3] = {0, 0, 0};
    size_t lampPhotons = 0, differing = 0, dark = 0;
    for (size_t i = 0; i < dev.size(); ++i) {
        for (int c = 0; c < 3; ++c) differing += dev[i].power[c] != twin[i].power[c];
        differing += dev[i].light != twin[i].light;
        if (!isLamp(r, r.buffers.lights[dev[i].light])) continue;
        ++lampPhotons;
        for (int c = 0; c < 3; ++c) {
            ASSERT_TRUE(std::isfinite(dev[i].power[c]));
            flux[c] += dev[i].power[c];
        }
        dark += dev[i].power[1] == 0.0f;  // the dark squares' G is 0
    }
    EXPECT_EQ(differing, 0u);
    EXPECT_GT(lampPhotons, kPhotons / 20);
    EXPECT_NEAR(double(dark) / double(lampPhotons), 0.125, 0.01) << "photons without green: the dark squares' middles";
    // ∫ L dA = A × factor × mean texel (half light, half dark squares).
    const Vec3 light(1.0f, 0.9f, 0.8f), darkTexel(0.05f, 0.0f, 0.1f), factor(6.0f, 5.0f, 4.0f);
    const double area = 0.8 * 0.6;
    for (int c = 0; c < 3; ++c) {
        const double want = kPiD * area * factor[c] * 0.5 * (double(light[c]) + darkTexel[c]);
        std::printf("[figure] textured lamp photon flux channel %d: %.5f W, pi int L dA = %.5f W (ratio %.4f)\n", c,
                    flux[c], want, flux[c] / want);
        EXPECT_NEAR(flux[c] / want, 1.0, 0.02) << "channel " << c;
    }
}

TEST(EmissionTextureCheck, EmitCheckPasses) {
    const PhotonCheckReport r = test::checkRoomPhotons(room(), "emit", 50000);
    EXPECT_TRUE(r.passed());
    ASSERT_FALSE(r.rows.empty());
    EXPECT_EQ(r.rows[0].maxPowerError, 0.0);
}

TEST(EmissionTextureCheck, WholePhotonPassMatchesTheTwin) {
    EXPECT_TRUE(test::checkRoomPhotons(room(), "pass", 10000).passed());
}

TEST(EmissionTextureCheck, EyeStagesAndFilmsMatchTheTwin) { test::expectRoomEyeStagesMatch(room()); }

}  // namespace
}  // namespace pcl
