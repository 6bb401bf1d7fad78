// Shading normals from per-vertex normals in the photon methods, against the reference path
// tracer (host/reference/surface.cpp interpolates the same normals): a closed room with a low-poly
// diffuse sphere and a low-poly glossy sphere (8 × 12 facets, vertex normals those of the true
// spheres), lit by a point light. Each photon method's image against the path tracer's at 48 × 36:
// the mean within 2 %, and per pixel over the two spheres' inner pixels, where faceted shading
// differs most: the mean squared relative difference from the smooth reference must be below the
// one from the faceted reference (the same scene without normals) by at least half the two
// references' own mean squared difference d². The method's noise adds alike to both, so the
// margin is what the normals change: a kernel that ignored them would sit closer to the faceted
// image (measured below, and with a mutated kernel). Figures are printed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "accuracy/accuracy_common.h"
#include "accuracy/pixel_stats.h"
#include "common/prepared_render.h"
#include "common/smooth_scenes.h"
#include "core/math.h"

using namespace pcl;
using namespace pcl::test_scenes;

namespace {

constexpr int kW = 48, kH = 36;
const Vec3 kDiffuseCentre(-0.45f, 0.4f, -0.3f), kGlossyCentre(0.1f, 0.3f, -0.6f);
constexpr float kDiffuseR = 0.4f, kGlossyR = 0.3f;

// The smooth room without its glass ball (a point light's caustics through glass are light
// paths the plain path tracer cannot find); `normals` false: the same spheres faceted.
Scene sphereRoom(bool normals) {
    Scene s;
    s.path = normals ? "(smooth spheres)" : "(faceted spheres)";
    const int plain = addMaterial(s, Vec3(0.6f));
    const int red = addMaterial(s, Vec3(0.7f, 0.2f, 0.2f));
    const int diffuse = addMaterial(s, Vec3(0.8f, 0.8f, 0.5f));
    const int glossy = addMaterial(s, Vec3(0.3f, 0.4f, 0.6f), Vec3(0.4f), SpecularKind::Glossy, Vec3(0.0f), 20.0f);
    addQuad(s, Vec3(-1, 0, 1), Vec3(2, 0, 0), Vec3(0, 0, -2), plain);
    addQuad(s, Vec3(-1, 0, -1), Vec3(2, 0, 0), Vec3(0, 2, 0), plain);
    addQuad(s, Vec3(-1, 2, -1), Vec3(2, 0, 0), Vec3(0, 0, 2), plain);
    addQuad(s, Vec3(-1, 0, 1), Vec3(0, 0, -2), Vec3(0, 2, 0), red);
    addQuad(s, Vec3(1, 0, -1), Vec3(0, 0, 2), Vec3(0, 2, 0), plain);
    addQuad(s, Vec3(1, 0, 1), Vec3(-2, 0, 0), Vec3(0, 2, 0), plain);
    addUvSphereMesh(s, kDiffuseCentre, kDiffuseR, 8, 12, diffuse, normals);
    addUvSphereMesh(s, kGlossyCentre, kGlossyR, 8, 12, glossy, normals);
    Light l = pointLight(Vec3(0.0f, 1.8f, 0.0f));
    l.intensity = Vec3(3.0f);
    s.lights.push_back(l);
    setCamera(s, Vec3(0.0f, 1.0f, 0.95f), Vec3(0.0f, 0.5f, -1.0f), Vec3(0, 1, 0), 70.0f, kW, kH);
    return s;
}

// Whether the whole of pixel (x, y) sees the sphere (c, r) well inside its silhouette (its four
// corners' rays hit the sphere of radius 0.85 r), so the faceted mesh covers it too.
bool insideSphere(const Camera& cam, int x, int y, Vec3 c, float r) {
    return sphereCoverage(cam, x, y, 2, c, 0.85f * r) == 1;
}

// Mean over the spheres' inner pixels and channels of ((a − b) / b)².
double sphereRelDiff(const Camera& cam, const Image& a, const Image& b, int& pixels) {
    double sum = 0.0;
    pixels = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            if (!insideSphere(cam, x, y, kDiffuseCentre, kDiffuseR) &&
                !insideSphere(cam, x, y, kGlossyCentre, kGlossyR))
                continue;
            for (int c = 0; c < 3; ++c) {
                const double r = (double(a.at(x, y)[c]) - b.at(x, y)[c]) / b.at(x, y)[c];
                sum += r * r;
            }
            ++pixels;
        }
    return pixels ? sum / (3.0 * pixels) : 0.0;
}

}  // namespace

TEST(SmoothNormalsAccuracy, PhotonMethodsMatchThePathTracerOnSmoothSpheres) {
    auto smooth = test::prepare(sphereRoom(true));
    auto faceted = test::prepare(sphereRoom(false));
    ASSERT_FALSE(smooth->buffers.triangleNormals.empty());
    ASSERT_TRUE(faceted->buffers.triangleNormals.empty());
    PhotonRenderSettings s;
    s.passes = 8;
    s.strata = 2;
    s.gatherRays = 16;
    s.globalPhotons = 100000;
    s.causticPhotons = 20000;
    s.seed = 11;
    const Image ref = test::renderImage(*smooth, RenderMethod::PathTracing, s, 1024, 5, "smooth spheres");
    const Image flat = test::renderImage(*faceted, RenderMethod::PathTracing, s, 1024, 5, "faceted spheres");
    int pixels = 0;
    const double d2 = sphereRelDiff(smooth->scene.camera, flat, ref, pixels);
    std::printf("[figure] smooth spheres: faceted vs smooth path-traced image over %d sphere pixels: mean squared "
                "relative difference d2 %.5f\n",
                pixels, d2);
    ASSERT_GT(pixels, 60);
    const double refMean = accuracy::meanValue(ref);
    for (RenderMethod m : {RenderMethod::FinalGather, RenderMethod::Progressive, RenderMethod::DirectVisualisation}) {
        const Image img = test::renderImage(*smooth, m, s, 0, 0, "smooth spheres");
        const double meanRatio = accuracy::meanValue(img) / refMean;
        const double toSmooth = sphereRelDiff(smooth->scene.camera, img, ref, pixels);
        const double toFaceted = sphereRelDiff(smooth->scene.camera, img, flat, pixels);
        std::printf("[figure] smooth spheres %s: mean / path %.4f; sphere pixels' mean squared rel diff to the smooth "
                    "reference %.5f, to the faceted one %.5f (margin %.2f d2)\n",
                    renderMethodName(m), meanRatio, toSmooth, toFaceted, (toFaceted - toSmooth) / d2);
        EXPECT_NEAR(meanRatio, 1.0, 0.02) << renderMethodName(m);
        EXPECT_GT(toFaceted - toSmooth, 0.5 * d2) << renderMethodName(m);
    }
}
