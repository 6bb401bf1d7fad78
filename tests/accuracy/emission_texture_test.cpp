// Emission textures against closed forms (scenes/README.md, "Textures": emission = factor ×
// texture).
//
// 1. A camera looking straight down at an emissive quad whose emission is factor × a 5 × 4
//    gradient (clamp): bilinear filtering reproduces the gradient exactly between the texel
//    centres, so the radiance seen is affine in film position and a box-filtered pixel must lie
//    between its footprint corners' values (1e-4 relative: round-off; nothing else lights the
//    scene, so there is no noise) with pixel / L(centre) averaging 1 within 1e-3 — for every
//    device method (fg, direct, progressive) and the reference path tracer.
// 2. A grey diffuse floor (ρ = 0.5) lit only by a small lamp 1 above it, facing down, whose
//    texture is black on its left 40 % (one quad of its own: those triangles read only black
//    texels, so they get no power and carry no light) and white beyond, with a linear ramp in
//    between (an 8 × 1 texture: black texels 0-3, white 4-7). The floor reflects L = ρ/π E,
//    E(x) = ∫ L_e(y) cos θx cos θy / r² dA_y, integrated here by the midpoint rule on a 200 × 200
//    grid over the lamp and averaged over each pixel's footprint (4 × 4 points). Nothing else
//    reaches the floor (the lamp's back is black, ρd 0). Compared as sums over the floor's right
//    (under the bright side) and left parts, pixels the lamp hides excluded: fg on the device
//    (next-event estimation of the lamp's texels, the gather rays' MIS against it) within 2 %,
//    the reference path tracer (its light sampler's texels, its MIS) within 2 %: both ~0.3-0.5 %
//    standard error over 432 pixels each (measured: fg 0.9990 left, 1.0004 right; path 0.9957,
//    1.0002). The right part is 1.33 times brighter than the left (a lamp emitting its factor
//    everywhere would light both alike), so a method that ignored the texture would miss by
//    far more than 2 %.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/prepared_render.h"
#include "common/textured_scenes.h"
#include "core/math.h"

using namespace pcl;
using namespace pcl::test_scenes;

namespace {

constexpr int kSize = 40;
const Vec3 kFactor(3.0f, 2.0f, 1.5f);

// The quad y = 0 (addQuadSeenFromAbove), facing the camera, emitting kFactor × the gradient.
Scene emissiveQuadScene() {
    Scene s;
    s.path = "(emissive textured quad)";
    const int t = addTexture(s, gradientImage(5, 4), TextureWrap::Clamp, TextureWrap::Clamp);
    const int m = addTexturedEmitter(s, t, kFactor);
    addQuadSeenFromAbove(s, m, kSize);
    addAreaLightFor(s, 0);
    return s;
}

GradientPixelError compareGradient(const Scene& scene, const Image& img) {
    return compareQuadGradient(scene.camera, img, kFactor);
}

// ---- 2: the half-lit floor -------------------------------------------------------------------

const Vec3 kLampFactor(8.0f, 6.0f, 4.0f);
constexpr float kRho = 0.5f;
constexpr float kLampY = 1.0f, kLampLo = -0.2f, kLampHi = 0.2f, kSplit = -0.04f;  // lamp x, z in [lo, hi]

Scene halfLitFloor() {
    Scene s;
    s.path = "(floor under a half-black lamp)";
    Image img(8, 1);
    for (int i = 4; i < 8; ++i) img.set(i, 0, Vec3(1.0f));
    const int t = addTexture(s, std::move(img), TextureWrap::Clamp, TextureWrap::Clamp);
    const int lamp = addTexturedEmitter(s, t, kLampFactor);
    const int floor = addMaterial(s, Vec3(kRho));
    addQuadSeenFromAbove(s, floor, kSize);
    // Facing down (u × v = −y); u = 0.4 at x = kSplit.
    const float w = kLampHi - kLampLo;
    const int left = addQuad(s, Vec3(kLampLo, kLampY, kLampLo), Vec3(kSplit - kLampLo, 0, 0), Vec3(0, 0, w), lamp);
    s.meshes[size_t(left)].uv[0] = {0.0f, 0.0f, 0.4f, 0.0f, 0.4f, 1.0f, 0.0f, 1.0f};
    const int right = addQuad(s, Vec3(kSplit, kLampY, kLampLo), Vec3(kLampHi - kSplit, 0, 0), Vec3(0, 0, w), lamp);
    s.meshes[size_t(right)].uv[0] = {0.4f, 0.0f, 1.0f, 0.0f, 1.0f, 1.0f, 0.4f, 1.0f};
    addAreaLightFor(s, left);
    addAreaLightFor(s, right);
    return s;
}

// The lamp's texture along x (bilinear, clamp, 8 texels: black 0-3, white 4-7).
float lampTexel(float x) {
    const float u = (x - kLampLo) / (kLampHi - kLampLo);
    return std::clamp(u * 8.0f - 0.5f - 3.0f, 0.0f, 1.0f);
}

// E at floor point (px, 0, pz) / the lamp's factor, by the midpoint rule.
double irradianceOverFactor(double px, double pz) {
    constexpr int n = 200;
    const double h = (kLampHi - kLampLo) / n;
    double sum = 0.0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double x = kLampLo + (i + 0.5) * h, z = kLampLo + (j + 0.5) * h;
            const double dx = x - px, dz = z - pz, r2 = dx * dx + kLampY * kLampY + dz * dz;
            sum += lampTexel(float(x)) * kLampY * kLampY / (r2 * r2);
        }
    return sum * h * h;
}

struct Halves {
    double got[2][3] = {{0, 0, 0}, {0, 0, 0}}, want[2][3] = {{0, 0, 0}, {0, 0, 0}};
    int pixels[2] = {0, 0};
};

// Sums over the floor's left (x < −0.3) and right (x > 0.3) parts; pixels whose rays the lamp
// could block excluded.
Halves sumHalves(const Scene& scene, const Image& img) {
    Halves h;
    const Camera& cam = scene.camera;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            float u0, v0, u1, v1;
            quadUvAt(cam, x, y, 0.0f, 0.0f, u0, v0);
            quadUvAt(cam, x, y, 1.0f, 1.0f, u1, v1);
            const float xLo = 2.0f * std::min(u0, u1) - 1.0f, xHi = 2.0f * std::max(u0, u1) - 1.0f;
            const float zLo = 1.0f - 2.0f * std::max(v0, v1), zHi = 1.0f - 2.0f * std::min(v0, v1);
            if (xLo < -1.0f || xHi > 1.0f || zLo < -1.0f || zHi > 1.0f) continue;
            const float hidden = kLampHi * cam.position.y / (cam.position.y - kLampY) + 0.05f;
            if (std::max(std::abs(xLo), std::abs(xHi)) < hidden && std::max(std::abs(zLo), std::abs(zHi)) < hidden)
                continue;
            int side = -1;
            if (xHi < -0.3f) side = 0;
            if (xLo > 0.3f) side = 1;
            if (side < 0) continue;
            const double e = pixelAverageOnGround(
                cam, x, y, [](Vec3 p) { return irradianceOverFactor(p.x, p.z); }, 4);
            for (int c = 0; c < 3; ++c) {
                h.got[side][c] += img.at(x, y)[c];
                h.want[side][c] += kRho / kPiD * kLampFactor[c] * e;
            }
            ++h.pixels[side];
        }
    return h;
}

}  // namespace

TEST(EmissionTexture, CameraSeesFactorTimesTexturePerPixel) {
    auto p = test::prepare(emissiveQuadScene());
    PhotonRenderSettings s;
    s.passes = 1;
    s.strata = 2;
    s.gatherRays = 4;
    s.globalPhotons = 2000;
    s.causticPhotons = 2000;
    s.seed = 3;
    for (RenderMethod m : {RenderMethod::FinalGather, RenderMethod::DirectVisualisation, RenderMethod::Progressive,
                           RenderMethod::PathTracing}) {
        const Image img = test::renderImage(*p, m, s, 8, 3, "emissive quad");
        const GradientPixelError e = compareGradient(p->scene, img);
        std::printf("[figure] emissive textured quad %s: %d pixels, worst outside the footprint's range %.2e, mean "
                    "pixel/L(centre) %.6f\n",
                    renderMethodName(m), e.compared, e.worstOutside, e.meanRatio);
        EXPECT_GT(e.compared, kSize * kSize / 3) << renderMethodName(m);
        EXPECT_LT(e.worstOutside, 1e-4) << renderMethodName(m);
        EXPECT_NEAR(e.meanRatio, 1.0, 1e-3) << renderMethodName(m);
    }
}

TEST(EmissionTexture, FloorUnderAHalfBlackLampMatchesTheIntegral) {
    auto p = test::prepare(halfLitFloor());
    // The left lamp quad reads only black texels: no power, so neither photons nor light samples.
    ASSERT_EQ(p->buffers.lights.size(), 4u);
    for (int k = 0; k < 2; ++k) EXPECT_EQ(p->buffers.lights[size_t(k)].power[0], 0.0f) << "left triangle " << k;
    for (int k = 2; k < 4; ++k) EXPECT_GT(p->buffers.lights[size_t(k)].power[0], 0.0f) << "right triangle " << k;

    PhotonRenderSettings s;
    s.passes = 2;
    s.strata = 3;
    s.gatherRays = 8;
    s.lightSamples = 4;
    s.globalPhotons = 20000;
    s.causticPhotons = 2000;
    s.seed = 5;
    const Image fg = test::renderImage(*p, RenderMethod::FinalGather, s, 0, 0, "half-lit floor");
    const Image path = test::renderImage(*p, RenderMethod::PathTracing, s, 64, 5, "half-lit floor");
    double ratioWant = 0.0;
    for (const auto& [what, img] : {std::make_pair("fg (device)", &fg), std::make_pair("path (reference)", &path)}) {
        const Halves h = sumHalves(p->scene, *img);
        ASSERT_GT(h.pixels[0], 100) << what;
        ASSERT_GT(h.pixels[1], 100) << what;
        for (int side = 0; side < 2; ++side)
            for (int c = 0; c < 3; ++c) {
                const double ratio = h.got[side][c] / h.want[side][c];
                std::printf(
                    "[figure] half-lit floor %s %s channel %d: %d pixels, sum %.5f, integral %.5f, ratio %.4f\n", what,
                    side ? "right" : "left", c, h.pixels[side], h.got[side][c], h.want[side][c], ratio);
                EXPECT_NEAR(ratio, 1.0, 0.02) << what << (side ? " right" : " left") << " channel " << c;
            }
        ratioWant = (h.want[1][0] / h.pixels[1]) / (h.want[0][0] / h.pixels[0]);
    }
    std::printf("[figure] half-lit floor: right/left mean radiance %.3f (the factor alone would light both alike)\n",
                ratioWant);
    EXPECT_GT(ratioWant, 1.25);
}
