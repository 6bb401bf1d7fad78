// Textured specular lobes per pixel against closed forms, for every render method (fg, direct,
// progressive on the device; the reference path tracer through its own lookups):
//
//  - A mirror quad whose ρs is a 5 × 4 gradient (ρd = 0) under a large emitter of radiance Le
//    facing it: every eye ray reflects once into the emitter, so L = ρs(uv) Le exactly.
//  - A glossy quad (ρd = 0) whose ρs is the gradient and whose exponent is 2 + 10 R of the same
//    gradient, lit by a directional light straight down: the glossy lobe's next-event estimate
//    L = ρs(uv) (e(uv) + 2)/(2π) cos^e(uv) α E cos θi, α the angle between the light and the
//    view ray's mirror direction (nothing else reaches the camera: no diffuse surface, and the
//    light is a delta light no ray can hit).
//
// Bilinear filtering reproduces the gradient (and so ρs and the exponent) exactly between its
// texel centres; only pixels whose whole footprint lies there are compared. A pixel averages L
// over its footprint (jittered samples): the expectation is L averaged on an 8 × 8 grid of the
// footprint. Bounds: the mirror's L is affine in film position, so its pixels lie within the
// footprint's corner values up to float round-off (1e-4 relative; measured 0 for every method,
// mean ratio 0.99998); the glossy L is not, so a pixel may differ from the grid average by the
// jitter's share: per pixel 2 % (measured 4.5e-3 on the device with 4 passes of 4 × 4 strata,
// 1.2e-2 for the path tracer's 256 random samples), the mean ratio within 1e-3 (measured
// 0.99996). A kernel that read the exponent from G instead of R fails it (shown once with
// PHOTONCL_KERNEL_DIR on a mutated copy of kernels/).
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
const Vec3 kLe(1.5f, 1.0f, 0.8f);
const Vec3 kIrradiance(2.0f, 1.5f, 1.0f);
const Vec3 kFactor(0.8f, 1.0f, 0.9f);
constexpr float kExpLo = 2.0f, kExpHi = 12.0f;

// The quad y = 0, x and z in [−1, 1], coordinates (0,0) at (−1, 0, 1), u along +x, v along −z;
// the camera 4 above it looking down.
Scene quadScene(bool glossy) {
    Scene s;
    s.path = glossy ? "(glossy textured quad)" : "(mirror textured quad)";
    const int t = addTexture(s, gradientImage(5, 4), TextureWrap::Clamp, TextureWrap::Clamp);
    const int m =
        addMaterial(s, Vec3(0.0f), kFactor, glossy ? SpecularKind::Glossy : SpecularKind::Mirror, Vec3(0.0f), kExpHi);
    s.materials[size_t(m)].rhoSTexture = t;
    if (glossy) {
        s.materials[size_t(m)].exponentTexture = t;
        s.materials[size_t(m)].exponentRange[0] = kExpLo;
        s.materials[size_t(m)].exponentRange[1] = kExpHi;
    }
    addQuadSeenFromAbove(s, m, kSize);
    if (glossy) {
        addDirectionalLight(s, Vec3(0, -1, 0), kIrradiance);
    } else {  // a 40 × 40 emitter at y = 6 facing down: every reflected ray meets it
        addQuad(s, Vec3(-20, 6, -20), Vec3(40, 0, 0), Vec3(0, 0, 40), addEmitter(s, Vec3(0.0f), kLe));
    }
    return s;
}

// The closed form at film point (x + fx, y + fy); uv returned for the region test.
Vec3 closedForm(const Camera& cam, bool glossy, int x, int y, float fx, float fy, float& u, float& v) {
    const Vec3 d = normalize(pinholeDirection(cam, x, y, fx, fy));
    const float t = -cam.position.y / d.y;
    const Vec3 p = cam.position + d * t;
    u = (p.x + 1.0f) / 2.0f;
    v = (1.0f - p.z) / 2.0f;
    const Vec3 rhoS = gradientAt(5, 4, u, v) * kFactor;
    if (!glossy) return rhoS * kLe;
    const float e = kExpLo + (kExpHi - kExpLo) * gradientAt(5, 4, u, v).x;
    const Vec3 r(d.x, -d.y, d.z);                // the mirror direction about n = +y
    const float cosAlpha = std::max(0.0f, r.y);  // the light comes from +y (cos θi = 1)
    return rhoS * kIrradiance * ((e + 2.0f) / (2.0f * kPi) * std::pow(cosAlpha, e));
}

struct PixelError {
    double worst = 0.0;      // mirror: relative distance outside the corners' range; glossy: |pixel/expected − 1|
    double meanRatio = 0.0;  // mean of pixel / expected over pixels and channels
    int compared = 0;
};

PixelError compare(const Scene& scene, bool glossy, const Image& img) {
    PixelError e;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            Vec3 lo(1e30f), hi(-1e30f), mean(0.0f);
            bool inside = true;
            constexpr int kGrid = 8;
            for (int j = 0; j <= kGrid; ++j)
                for (int i = 0; i <= kGrid; ++i) {
                    float u, v;
                    const Vec3 L = closedForm(scene.camera, glossy, x, y, float(i) / kGrid, float(j) / kGrid, u, v);
                    // The exact region of a 5 × 4 gradient: between the outer texel centres.
                    inside = inside && u >= 0.1f && u <= 0.9f && v >= 0.125f && v <= 0.875f;
                    lo = vmin(lo, L);
                    hi = vmax(hi, L);
                    if (i < kGrid && j < kGrid) {
                        float uc, vc;
                        mean += closedForm(scene.camera, glossy, x, y, (float(i) + 0.5f) / kGrid,
                                           (float(j) + 0.5f) / kGrid, uc, vc) /
                                Vec3(float(kGrid * kGrid));
                    }
                }
            if (!inside) continue;
            const Vec3 got = img.at(x, y);
            for (int c = 0; c < 3; ++c) {
                const double err = glossy ? std::abs(double(got[c]) / mean[c] - 1.0)
                                          : std::max({0.0, double(lo[c]) - got[c], double(got[c]) - hi[c]}) / mean[c];
                e.worst = std::max(e.worst, err);
                e.meanRatio += double(got[c]) / mean[c];
            }
            ++e.compared;
        }
    e.meanRatio /= std::max(1, 3 * e.compared);
    return e;
}

void checkEveryMethod(bool glossy, double worstBound, double meanBound) {
    auto p = test::prepare(quadScene(glossy));
    PhotonRenderSettings s;
    s.passes = 4;
    s.strata = 4;
    s.gatherRays = 4;
    s.globalPhotons = 2000;
    s.causticPhotons = 2000;
    s.seed = 5;
    for (RenderMethod m : {RenderMethod::FinalGather, RenderMethod::DirectVisualisation, RenderMethod::Progressive,
                           RenderMethod::PathTracing}) {
        const Image img = test::renderImage(*p, m, s, 256, 7, p->scene.path);
        const PixelError e = compare(p->scene, glossy, img);
        std::printf("[figure] %s %s: %d pixels, worst %.2e, mean pixel/expected %.6f\n", p->scene.path.c_str(),
                    renderMethodName(m), e.compared, e.worst, e.meanRatio);
        EXPECT_GT(e.compared, kSize * kSize / 3) << renderMethodName(m);
        EXPECT_LT(e.worst, worstBound) << renderMethodName(m);
        EXPECT_NEAR(e.meanRatio, 1.0, meanBound) << renderMethodName(m);
    }
}

}  // namespace

TEST(TexturedSpecularQuad, MirrorWithTexturedRhoSReflectsRhoSTimesLe) { checkEveryMethod(false, 1e-4, 1e-4); }

TEST(TexturedSpecularQuad, GlossyWithTexturedRhoSAndExponentMatchesThePhongLobe) { checkEveryMethod(true, 2e-2, 1e-3); }
