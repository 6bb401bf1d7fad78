// A textured quad under a directional light, per pixel against the closed form
// L = ρd(uv) / π · E: the texture is a 5 × 4 gradient that bilinear filtering reproduces exactly
// between its texel centres, and the camera looks straight down, so L is affine in film position.
// Only pixels whose whole footprint lies within the exact region are compared. A box-filtered
// pixel averages L at its jittered samples, so it must lie between L's values at its footprint's
// corners (within 1e-4 relative: float round-off; the light is a delta light and the quad alone
// reflects nothing back to itself, so there is no other noise), and pixel / L(centre) must
// average to 1 within 1e-3 over the ~700 pixels (the jitter's share, measured ~1e-4). Rendered by
// the device's final gathering (direct light at the textured eye hit) and the reference path
// tracer (the twin's lookup).
//
// And Jensen's practice: the preview (direct visualisation of the global map) multiplies the
// blurry irradiance estimate by the shading point's textured ρd, so a checkerboard stays sharp:
// pixel / (ρd(uv)/π) recovers E on the dark squares and on the light ones alike (within 3 %,
// over each colour's interior pixels; an estimate that took ρd from the photons instead would
// blur the squares into each other).
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
const Vec3 kIrradiance(2.0f, 1.5f, 1.0f);
const Vec3 kFactor(0.8f, 1.0f, 0.9f);

// The quad y = 0, x and z in [−1, 1], coordinates (0,0) at (−1, 0, 1), u along +x, v along −z.
Scene quadScene(Image texture) {
    Scene s;
    s.path = "(textured quad)";
    const int t = addTexture(s, std::move(texture), TextureWrap::Clamp, TextureWrap::Clamp);
    const int m = addMaterial(s, kFactor);
    s.materials[size_t(m)].rhoDTexture = t;
    addQuadSeenFromAbove(s, m, kSize);
    addDirectionalLight(s, Vec3(0, -1, 0), kIrradiance);
    return s;
}

GradientPixelError compareGradient(const Scene& scene, const Image& img) {
    return compareQuadGradient(scene.camera, img, kFactor * kIrradiance / Vec3(kPi));
}

}  // namespace

TEST(TexturedQuad, DirectLightPerPixelMatchesTextureTimesRhoOverPiTimesE) {
    auto p = test::prepare(quadScene(gradientImage(5, 4)));
    PhotonRenderSettings s;
    s.passes = 2;
    s.strata = 2;
    s.gatherRays = 4;
    s.globalPhotons = 2000;
    s.causticPhotons = 2000;
    s.seed = 3;
    const Image fg = test::renderImage(*p, RenderMethod::FinalGather, s, 0, 0, "textured quad");
    const GradientPixelError efg = compareGradient(p->scene, fg);
    const Image path = test::renderImage(*p, RenderMethod::PathTracing, s, 8, 3, "textured quad");
    const GradientPixelError ept = compareGradient(p->scene, path);
    for (const auto& [what, e] : {std::make_pair("fg (device)", efg), std::make_pair("path (twin lookup)", ept)}) {
        std::printf("[figure] textured quad %s: %d pixels, worst outside the footprint's range %.2e, mean "
                    "pixel/L(centre) %.6f\n",
                    what, e.compared, e.worstOutside, e.meanRatio);
        EXPECT_GT(e.compared, kSize * kSize / 3) << what;
        EXPECT_LT(e.worstOutside, 1e-4) << what;
        EXPECT_NEAR(e.meanRatio, 1.0, 1e-3) << what;
    }
}

TEST(TexturedQuad, PhotonMapPreviewKeepsTheTextureSharp) {
    // 8 × 8 texels, squares of 2 × 2: light (0.9) and dark (0.1) in every channel.
    auto p = test::prepare(quadScene(checkerImage(8, 8, 2, Vec3(0.9f), Vec3(0.1f))));
    PhotonRenderSettings s;
    s.passes = 4;
    s.globalPhotons = 200000;
    s.seed = 9;
    const Image img = test::renderImage(*p, RenderMethod::DirectVisualisation, s, 0, 0, "textured quad preview");
    // E recovered per pixel, averaged over the flat middles of the four inner squares (between
    // the centres of a square's texels, where bilinear filtering blends nothing in; away from the
    // quad's rim, where the estimate's disc reaches past the quad).
    double sum[2] = {0, 0};
    int count[2] = {0, 0};
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            for (int i = 1; i < 3; ++i)
                for (int j = 1; j < 3; ++j) {
                    const float lo = (2.0f * float(i) + 0.5f) / 8.0f, hi = (2.0f * float(i) + 1.5f) / 8.0f;
                    const float loV = (2.0f * float(j) + 0.5f) / 8.0f, hiV = (2.0f * float(j) + 1.5f) / 8.0f;
                    if (!quadFootprintInside(p->scene.camera, x, y, lo, hi, loV, hiV)) continue;
                    const bool light = (i + j) % 2 == 0;
                    const float rho = (light ? 0.9f : 0.1f) * kFactor.x;
                    sum[light] += double(img.at(x, y).x) / (rho / kPi);
                    ++count[light];
                }
        }
    ASSERT_GT(count[0], 4);
    ASSERT_GT(count[1], 4);
    const double dark = sum[0] / count[0], light = sum[1] / count[1];
    std::printf("[figure] textured quad preview: E from dark squares %.4f, light squares %.4f, expected %.4f\n", dark,
                light, double(kIrradiance.x));
    EXPECT_NEAR(dark / kIrradiance.x, 1.0, 0.03);
    EXPECT_NEAR(light / kIrradiance.x, 1.0, 0.03);
}
