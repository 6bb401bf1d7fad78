// Accuracy of the reference light tracer (reference/light_tracer.h): closed-form caustics by the
// image-source method (a spot light's image in a mirror, the sun reflected by a mirror wall seen
// through a thin lens), agreement with the path tracer on every path from a point light where
// both can find them, no light at all where the path tracer needs none, and the same bits for
// any thread count. Tolerances stand beside the standard errors they were chosen against.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "accuracy/accuracy_common.h"
#include "accuracy/pixel_stats.h"
#include "common/test_scenes.h"
#include "core/error.h"
#include "geometry/scene_geometry.h"
#include "image/film.h"
#include "image/metrics.h"
#include "reference/camera.h"
#include "reference/light_tracer.h"
#include "reference/path_tracer.h"
#include "reference/sampling.h"
#include "reference/surface.h"
#include "render/path_render.h"

using namespace pcl;
using namespace pcl::test_scenes;

namespace {

// The light tracer's estimate alone, as an image: `passes` passes of width × height paths.
Image lightTraced(const Scene& scene, const SceneGeometry& geometry, uint32_t passes, uint64_t seed,
                  LightTracerPaths paths, int maxDepth = 64, int threads = 2, Film* filmOut = nullptr) {
    LightTracerSettings s;
    s.seed = seed;
    s.passes = passes;
    s.threads = threads;
    s.maxDepth = maxDepth;
    s.paths = paths;
    Film film(scene.camera.width, scene.camera.height);
    LightTracerStats stats;
    LightTracer(scene, geometry, s).render(film, &stats);
    EXPECT_EQ(stats.discarded, 0u);
    if (filmOut) *filmOut = film;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) film.add(x, y, Vec3(0.0f), passes);  // the passes' weight
    return film.resolve();
}

}  // namespace

// A spot light at height h under a mirror ceiling at height H, pointing up: its mirror image is
// a spot at height 2H − h pointing down, so the floor (albedo ρ) reflects
// L = ρ/π · ρm I(θ) cosθ / r² from the image (image-source method), θ the angle at the image
// between its axis and the floor point. Only the light tracer's first-order paths (L S D E, at
// most one bounce after the mirror) are rendered, per pixel against the closed form.
TEST(LightTracerAccuracy, SpotLightMirroredByACeilingMatchesTheImageSource) {
    Scene scene;
    int floor = addMaterial(scene, Vec3(0.5f, 0.25f, 0.8f));
    int mirror = addMaterial(scene, Vec3(0.0f), Vec3(0.9f, 0.8f, 0.7f), SpecularKind::Mirror);
    addQuad(scene, Vec3(-50, 0, -50), Vec3(0, 0, 100), Vec3(100, 0, 0), floor);   // faces up
    addQuad(scene, Vec3(-50, 2, -50), Vec3(100, 0, 0), Vec3(0, 0, 100), mirror);  // faces down
    Light spot;
    spot.type = LightType::Spot;
    spot.name = "spot";
    spot.position = {0.3f, 1.2f, -0.2f};
    spot.direction = {0.0f, 1.0f, 0.0f};
    spot.intensity = Vec3(10.0f, 7.0f, 4.0f);
    spot.cosInner = std::cos(35.0f * kPi / 180.0f);  // the camera sees only floor inside the inner cone
    spot.cosOuter = std::cos(40.0f * kPi / 180.0f);
    scene.lights.push_back(spot);
    setCamera(scene, {0.3f, 1.8f, 0.3f}, {0.3f, 0.0f, -0.2f}, {0, 0, -1}, 40.0f, 12, 12);
    SceneGeometry geometry = SceneGeometry::build(scene);
    EXPECT_NE(pathsThePathTracerMisses(scene), "");
    Image img = lightTraced(scene, geometry, 20000, testSeed(5), LightTracerPaths::ThroughSpecular, 1);

    const Vec3 image(spot.position.x, 2.0f * 2.0f - spot.position.y, spot.position.z);
    const Vec3 rhoM = scene.materials[mirror].rhoS;
    double worst = 0.0, sumRatio = 0.0, sumExpected = 0.0, sumSq = 0.0;
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 12; ++x)
            for (int c = 0; c < 3; ++c) {
                double expected = pixelAverageOnGround(scene.camera, x, y, [&](Vec3 p) {
                    Vec3 d = p - image;
                    double r2 = dot(d, d), cosTheta = -d.y / std::sqrt(r2);  // at the image and the floor
                    double I = spot.intensity[c] * smoothstep(spot.cosOuter, spot.cosInner, float(cosTheta));
                    return scene.materials[floor].rhoD[c] / kPi * rhoM[c] * I * cosTheta / r2;
                });
                double ratio = img.at(x, y)[c] / expected;
                worst = std::max(worst, std::abs(ratio - 1.0));
                sumSq += (ratio - 1.0) * (ratio - 1.0);
                sumRatio += img.at(x, y)[c];
                sumExpected += expected;
            }
    std::printf("mirrored spot: mean ratio %.5f, pixels: rms %.3f%%, worst %.3f%%\n", sumRatio / sumExpected,
                100.0 * std::sqrt(sumSq / (12 * 12 * 3)), 100.0 * worst);
    // Pixel values scatter by 1.6-1.9 % rms (noise only; seeds 5, 1005, 2005): the worst within 5σ.
    // The channels share their paths, so σ(mean) ≈ 1.8 % / √144 = 0.15 % (measured +0.34 % at most).
    EXPECT_NEAR(sumRatio / sumExpected, 1.0, 0.006);
    EXPECT_LT(worst, 0.095);
}

// A point light at the centre of a glass ball (η = 1.5): every ray meets the surface at normal
// incidence, leaves with T = 1 − F (F = 0.04) or is reflected through the centre and leaves on the
// far side, still radial, so outside the ball the light is a point light of intensity T(1 + F) I
// (paths with two internal reflections and more cut off by maxDepth 2). Flux crosses the surface
// unscaled: the radiance's (η_i/η_t)² (2.25 here) must not be applied to light paths.
TEST(LightTracerAccuracy, PointLightInsideAGlassBallShinesWithTheTransmittedFlux) {
    Scene scene;
    int floor = addMaterial(scene, Vec3(0.3f, 0.5f, 0.7f));
    int glass = addMaterial(scene, Vec3(0.0f), Vec3(1.0f), SpecularKind::Dielectric);
    scene.materials[glass].ior = 1.5f;
    addQuad(scene, Vec3(-50, 0, -50), Vec3(0, 0, 100), Vec3(100, 0, 0), floor);  // faces up
    const Vec3 centre(0.0f, 0.4f, 0.0f);
    addSphere(scene, centre, 0.05f, glass);
    Light bulb = pointLight(centre);
    bulb.name = "bulb";
    bulb.intensity = Vec3(2.0f, 1.0f, 0.5f);
    scene.lights.push_back(bulb);
    setCamera(scene, {0.2f, 0.3f, 0.0f}, {0.2f, 0.0f, 0.0f}, {0, 0, -1}, 90.0f, 12, 12);  // below the ball
    SceneGeometry geometry = SceneGeometry::build(scene);
    Image img = lightTraced(scene, geometry, 10000, testSeed(13), LightTracerPaths::ThroughSpecular, 2);

    const double F = 0.04, transmitted = (1.0 - F) * (1.0 + F);
    double worst = 0.0, sum = 0.0, sumExpected = 0.0, sumSq = 0.0;
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 12; ++x)
            for (int c = 0; c < 3; ++c) {
                double expected = pixelAverageOnGround(scene.camera, x, y, [&](Vec3 p) {
                    Vec3 d = centre - p;
                    double r2 = dot(d, d), cosTheta = d.y / std::sqrt(r2);
                    return scene.materials[floor].rhoD[c] / kPi * transmitted * bulb.intensity[c] * cosTheta / r2;
                });
                double ratio = img.at(x, y)[c] / expected;
                worst = std::max(worst, std::abs(ratio - 1.0));
                sumSq += (ratio - 1.0) * (ratio - 1.0);
                sum += img.at(x, y)[c];
                sumExpected += expected;
            }
    std::printf("point light inside glass: mean ratio %.5f, pixels: rms %.3f%%, worst %.3f%%\n", sum / sumExpected,
                100.0 * std::sqrt(sumSq / (12 * 12 * 3)), 100.0 * worst);
    // Pixel values scatter by 3.3-3.7 % rms (seeds 13, 1013, 2013; channels share their paths):
    // σ(mean) ≈ 3.5 % / √144 = 0.3 % (measured +0.34 % at most); the worst pixel within ~4σ.
    // With the radiance's η² applied to flux the mean reads 2.25.
    EXPECT_NEAR(sum / sumExpected, 1.0, 0.01);
    EXPECT_LT(worst, 0.15);
}

// The sun reflected by a mirror wall onto a floor, through a thin lens with the shutter open:
// parallel light stays parallel, so the floor (albedo ρ) is lit uniformly, E = ρm E⊥ cosθ, and
// every pixel sees L = ρ/π ρm E⊥ cosθ whatever the defocus: the lens importance, the shutter
// time and the directional light's disc must all be right for the numbers to match.
TEST(LightTracerAccuracy, SunReflectedByAMirrorWallThroughAThinLens) {
    Scene scene;
    int floor = addMaterial(scene, Vec3(0.6f, 0.5f, 0.3f));
    int mirror = addMaterial(scene, Vec3(0.0f), Vec3(0.8f), SpecularKind::Mirror);
    addQuad(scene, Vec3(0.8f, 0, -1.2f), Vec3(0, 0, 2.4f), Vec3(2.4f, 0, 0), floor);  // faces up
    addQuad(scene, Vec3(0, 0, -1.2f), Vec3(0, 3.3f, 0), Vec3(0, 0, 2.4f), mirror);    // x = 0, faces +x
    Light sun;
    sun.type = LightType::Directional;
    sun.name = "sun";
    sun.direction = normalize(Vec3(-1.0f, -1.0f, 0.0f));  // reflected: (1, -1, 0)/√2, lands at x = y
    sun.irradiance = Vec3(2.0f, 1.5f, 1.0f);
    scene.lights.push_back(sun);
    setCamera(scene, {2.0f, 2.5f, 0.0f}, {2.0f, 0.0f, 0.0f}, {0, 0, 1}, 30.0f, 12, 12);
    scene.camera.model = CameraModel::ThinLens;
    scene.camera.apertureRadius = 0.15f;
    scene.camera.focusDistance = 1.5f;  // the floor is a metre behind the plane of focus
    scene.camera.shutterOpen = 0.0f;
    scene.camera.shutterClose = 0.01f;
    SceneGeometry geometry = SceneGeometry::build(scene);
    Image img = lightTraced(scene, geometry, 32000, testSeed(9), LightTracerPaths::ThroughSpecular, 1);

    const float cosFloor = std::sqrt(0.5f);
    double worst = 0.0, sum = 0.0, sumExpected = 0.0, sumSq = 0.0;
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 12; ++x)
            for (int c = 0; c < 3; ++c) {
                double expected = scene.materials[floor].rhoD[c] / kPi * 0.8 * sun.irradiance[c] * cosFloor;
                double ratio = img.at(x, y)[c] / expected;
                worst = std::max(worst, std::abs(ratio - 1.0));
                sumSq += (ratio - 1.0) * (ratio - 1.0);
                if (std::getenv("PHOTONCL_TEST_VERBOSE") && c == 0) std::printf("%6.3f%s", ratio, x == 11 ? "\n" : " ");
                sum += img.at(x, y)[c];
                sumExpected += expected;
            }
    std::printf("reflected sun through a thin lens: mean ratio %.5f, pixels: rms %.3f%%, worst %.3f%%\n",
                sum / sumExpected, 100.0 * std::sqrt(sumSq / (12 * 12 * 3)), 100.0 * worst);
    // Pixel values scatter by 2.2-2.6 % rms (noise only; seeds 9, 1009, 2009): the worst within 5σ;
    // σ(mean) ≈ 2.5 % / √144 = 0.2 % (measured +0.38 % at most).
    EXPECT_NEAR(sum / sumExpected, 1.0, 0.008);
    EXPECT_LT(worst, 0.11);
}

// Where both estimators find every path — a point light, diffuse surfaces only — the light
// tracer counting all paths from the light (L D+ E) must agree with the path tracer (next-event
// estimation): per pixel (Z-test, 8 renders each) and in the mean. Its ThroughSpecular share, the
// part added to the reference, is exactly zero there, as it is in an area-lit scene.
TEST(LightTracerAccuracy, AgreesWithThePathTracerWhereBothFindEveryPath) {
    Scene scene = accuracy::loadSceneAt("cornell-spheres-point.json", 16, 16);
    for (Material& m : scene.materials)
        if (m.specular != SpecularKind::None) {  // the mirror and glass balls become grey diffuse
            m.specular = SpecularKind::None;
            m.rhoD = Vec3(0.5f);
        }
    ASSERT_EQ(pathsThePathTracerMisses(scene), "");
    SceneGeometry geometry = SceneGeometry::build(scene);

    const int K = 8;
    std::vector<Image> light, path;
    PathTracerSettings pt;
    pt.samplesPerPixel = 1024;
    pt.threads = 2;
    for (int k = 0; k < K; ++k) {
        light.push_back(lightTraced(scene, geometry, 2048, testSeed(100 + k), LightTracerPaths::All));
        pt.seed = testSeed(200 + k);
        path.push_back(PathTracer(scene, geometry, pt).render().resolve());
    }
    // The path tracer's K renders as the reference, with their variance of the mean.
    Image mean(16, 16), variance(16, 16);
    for (size_t i = 0; i < mean.pixelCount(); ++i) {
        double s = 0.0, s2 = 0.0;
        for (int c = 0; c < 3; ++c) mean.rgb[3 * i + c] = 0.0f;
        for (const Image& p : path) {
            double v = double(p.rgb[3 * i]) + p.rgb[3 * i + 1] + p.rgb[3 * i + 2];
            s += v;
            s2 += v * v;
            for (int c = 0; c < 3; ++c) mean.rgb[3 * i + c] += p.rgb[3 * i + c] / K;
        }
        variance.rgb[3 * i] = float((s2 - s * s / K) / (K - 1) / K);
    }
    ZTestResult z = perPixelZTest(light, mean, 4.0, &variance);
    double lightMean = 0.0;
    for (const Image& l : light) lightMean += accuracy::meanValue(l) / K;
    const double ratio = lightMean / accuracy::meanValue(mean);
    std::printf("light tracer (all paths) vs path tracer: mean ratio %.5f; %s\n", ratio, formatZTest(z).c_str());
    // Seeds 0-2: mean ratio 0.99883-1.00019, 254-256 of 256 pixels pass (t with 7 dof:
    // P(|t| > 4) ≈ 0.5 %).
    EXPECT_NEAR(ratio, 1.0, 0.005);
    EXPECT_GE(z.passFraction(), 0.97);
    EXPECT_EQ(z.nonFinite, 0u);

    // No paths through specular surfaces: the reference's light-traced share is exactly zero.
    Film share(16, 16);
    lightTraced(scene, geometry, 64, 1, LightTracerPaths::ThroughSpecular, 64, 2, &share);
    for (double v : share.sums()) ASSERT_EQ(v, 0.0);
    Scene areaLit = accuracy::loadSceneAt("cornell-box.json", 16, 16);
    EXPECT_EQ(pathsThePathTracerMisses(areaLit), "");
    SceneGeometry areaGeometry = SceneGeometry::build(areaLit);
    Film none(16, 16);
    LightTracerSettings all;
    all.paths = LightTracerPaths::All;
    LightTracerStats stats;
    LightTracer(areaLit, areaGeometry, all).render(none, &stats);
    EXPECT_EQ(stats.paths, 0u);  // no delta lights: nothing to trace
    for (double v : none.sums()) ASSERT_EQ(v, 0.0);
}

// Emission aimed at the mirror and glass balls (cones from a point light, discs across a
// directional light's beam) against uniform emission, ThroughSpecular, at the same passes (so
// about the same number of specular first bounces): the same image in the mean and per 2×2
// block (Z-test of 8 renders each, both sides' variance). cornell-spheres-point (point light,
// two balls), motion-dof (sun, chrome ball, thin lens, shutter: the reflected sun is sparse, so
// its blocks are noisier).
TEST(LightTracerAccuracy, AimedEmissionAgreesWithUniformEmission) {
    for (const char* name : {"cornell-spheres-point.json", "motion-dof.json"}) {
        Scene scene = accuracy::loadSceneAt(name, 16, 12);
        SceneGeometry geometry = SceneGeometry::build(scene);
        const int K = 8;
        uint32_t passes = 8000;
        if (const char* scale = std::getenv("PHOTONCL_TEST_SPP_SCALE")) passes *= std::max(1, std::atoi(scale));
        std::vector<Image> aimed, uniform;
        LightTracerSettings s;
        s.threads = 2;
        s.passes = passes;
        for (int k = 0; k < K; ++k) {
            for (bool aim : {true, false}) {
                s.seed = testSeed((aim ? 300 : 400) + k);
                s.aim = aim;
                LightTracer tracer(scene, geometry, s);
                if (aim) {
                    EXPECT_LT(tracer.pathsPerPass(), 16u * 12u / 10u);  // a few % of directions hit a ball
                } else {
                    EXPECT_EQ(tracer.pathsPerPass(), 16u * 12u);
                }
                Film f(16, 12);
                tracer.render(f);
                for (int y = 0; y < 12; ++y)
                    for (int x = 0; x < 16; ++x) f.add(x, y, Vec3(0.0f), passes);
                (aim ? aimed : uniform).push_back(boxDownsample(f.resolve(), 2));
            }
        }
        Image mean(8, 6), variance(8, 6);
        for (size_t i = 0; i < mean.pixelCount(); ++i) {
            double sum = 0.0, sum2 = 0.0;
            for (const Image& u : uniform) {
                double v = double(u.rgb[3 * i]) + u.rgb[3 * i + 1] + u.rgb[3 * i + 2];
                sum += v;
                sum2 += v * v;
                for (int c = 0; c < 3; ++c) mean.rgb[3 * i + c] += u.rgb[3 * i + c] / K;
            }
            variance.rgb[3 * i] = float((sum2 - sum * sum / K) / (K - 1) / K);
        }
        ZTestResult z = perPixelZTest(aimed, mean, 4.0, &variance);
        double aimedMean = 0.0;
        for (const Image& a : aimed) aimedMean += accuracy::meanValue(a) / K;
        const double ratio = aimedMean / accuracy::meanValue(mean);
        if (std::getenv("PHOTONCL_TEST_VERBOSE"))
            for (int k = 0; k < K; ++k)
                std::printf("  run %d: aimed %.6f uniform %.6f\n", k, accuracy::meanValue(aimed[k]),
                            accuracy::meanValue(uniform[k]));
        std::printf("%s: aimed / uniform emission: mean ratio %.5f; 2x2 blocks %s\n", name, ratio,
                    formatZTest(z).c_str());
        // Run means scatter by 0.3 % (cornell-spheres-point) and 3 % (motion-dof: a few reflected
        // sun rays reach the view) at 8000 passes: σ(ratio) ≈ 0.15 % and 1.6 %. Measured over
        // seeds 0-1: 0.9993-1.0010 and 0.986-0.990; at 4× the passes 0.9991 and 1.0067.
        EXPECT_NEAR(ratio, 1.0, name == std::string("motion-dof.json") ? 0.06 : 0.006) << name;
        EXPECT_GE(z.passFraction(), 0.95) << name;
    }
}

// The same seed gives the same film bits with 1 and 3 threads, passes split in two add up to
// the one-call film's bits, and another seed changes it.
TEST(LightTracerAccuracy, DeterministicAcrossThreadsAndPasses) {
    Scene scene = accuracy::loadSceneAt("cornell-spheres-point.json", 40, 40);
    SceneGeometry geometry = SceneGeometry::build(scene);
    Film one, three, split, other;
    lightTraced(scene, geometry, 4, 3, LightTracerPaths::ThroughSpecular, 64, 1, &one);
    lightTraced(scene, geometry, 4, 3, LightTracerPaths::ThroughSpecular, 64, 3, &three);
    EXPECT_EQ(one.sums(), three.sums());
    double total = 0.0;
    for (double v : one.sums()) total += v;
    EXPECT_GT(total, 0.0);  // the caustics are there

    LightTracerSettings s;
    s.seed = 3;
    s.threads = 2;
    s.passes = 1;
    split = Film(40, 40);
    LightTracer(scene, geometry, s).render(split);
    s.firstPass = 1;
    s.passes = 3;
    LightTracer(scene, geometry, s).render(split);
    EXPECT_EQ(split.sums(), one.sums());  // splats are added pass by pass, in path order, either way
    lightTraced(scene, geometry, 4, 4, LightTracerPaths::ThroughSpecular, 64, 2, &other);
    EXPECT_NE(other.sums(), one.sums());
}

// render --method path's loop (render/path_render.h) adds the light tracer where the scene needs
// it, one pass of light paths per sample per pixel, and keeps its promises: all
// samples in one call and one sample at a time give the same bits; fixed-point sums (batch
// shards) agree to rounding; without light tracing it is the path tracer alone, and darker.
TEST(LightTracerAccuracy, PathRenderAddsTheLightTracerWhereTheSceneNeedsIt) {
    Scene scene = accuracy::loadSceneAt("cornell-spheres-point.json", 24, 24);
    SceneGeometry geometry = SceneGeometry::build(scene);
    PathRenderSettings s;
    s.seed = 3;
    s.samples = 3;
    s.threads = 2;
    PathRenderResult once = renderPathTraced(scene, geometry, s);
    EXPECT_NE(once.lightTracing.find("point light 'ceiling-point'"), std::string::npos) << once.lightTracing;
    const uint32_t perPass = LightTracer(scene, geometry, LightTracerSettings{}).pathsPerPass();
    EXPECT_GT(perPass, 0u);
    EXPECT_LT(perPass, 24u * 24u / 10u);  // aimed at the balls: 3.5 % of a uniform pass's directions
    EXPECT_EQ(once.lightPaths, 3u * perPass);
    EXPECT_GT(once.lightSplats, 0u);
    EXPECT_EQ(once.discarded, 0u);

    PathRenderSettings oneAtATime = s;
    oneAtATime.seconds = 1e6;  // a budget: one sample per pixel per call
    EXPECT_EQ(renderPathTraced(scene, geometry, oneAtATime).film.sums(), once.film.sums());

    PathRenderSettings fixed = s;
    fixed.fixedPoint = true;
    const Image a = once.film.resolve(), b = renderPathTraced(scene, geometry, fixed).sums.resolve();
    for (size_t i = 0; i < a.rgb.size(); ++i) ASSERT_NEAR(b.rgb[i], a.rgb[i], 1e-6 * (1.0 + a.rgb[i])) << i;

    PathRenderSettings alone = s;
    alone.lightTracing = false;
    PathRenderResult pathOnly = renderPathTraced(scene, geometry, alone);
    EXPECT_EQ(pathOnly.lightTracing, "");
    EXPECT_EQ(pathOnly.lightPaths, 0u);
    PathTracerSettings pt;
    pt.seed = 3;
    pt.samplesPerPixel = 3;
    EXPECT_EQ(pathOnly.film.sums(), PathTracer(scene, geometry, pt).render().sums());
    EXPECT_GT(accuracy::meanValue(a), accuracy::meanValue(pathOnly.film.resolve()));

    // In fog the light tracer would miss the medium: refused, unless the user renders without it.
    Medium fog;
    fog.name = "fog";
    fog.sigmaS = Vec3(0.05f);
    scene.media.push_back(fog);
    scene.globalMedium = 0;
    try {
        renderPathTraced(scene, geometry, s);
        ADD_FAILURE() << "a light-traced scene with a medium rendered";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("does not trace media"), std::string::npos) << e.what();
    }
    EXPECT_EQ(renderPathTraced(scene, geometry, alone).lightPaths, 0u);
}

// The pixels `compare --skip-specular-pixels` leaves out: a mirror ball and a glass ball in front
// of a diffuse wall (a glossy ball is no delta lobe: kept), viewed straight on. A pixel is left
// out exactly when one of its 4 × 4 sample rays meets a delta ball, by the closed-form ray–sphere
// test on the same rays.
TEST(LightTracerAccuracy, SpecularPixelMaskHoldsThePixelsThatSeeMirrorsOrGlassFirst) {
    Scene scene;
    const int wall = addMaterial(scene, Vec3(0.5f));
    const int mirror = addMaterial(scene, Vec3(0.0f), Vec3(0.9f), SpecularKind::Mirror);
    const int glass = addGlass(scene, 1.5f);
    const int glossy = addMaterial(scene, Vec3(0.3f), Vec3(0.5f), SpecularKind::Glossy);
    scene.materials[glossy].phongExponent = 50.0f;
    addQuad(scene, Vec3(-5, -5, 2), Vec3(10, 0, 0), Vec3(0, 10, 0), wall);
    struct Ball {
        Vec3 c;
        float r;
        bool delta;
    };
    const Ball balls[] = {{Vec3(-0.6f, 0.0f, 0.0f), 0.35f, true},
                          {Vec3(0.6f, 0.1f, 0.5f), 0.3f, true},
                          {Vec3(0.0f, -0.7f, 0.2f), 0.25f, false}};
    addSphere(scene, balls[0].c, balls[0].r, mirror);
    addSphere(scene, balls[1].c, balls[1].r, glass);
    addSphere(scene, balls[2].c, balls[2].r, glossy);
    setCamera(scene, {0.0f, 0.0f, -4.0f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 40.0f, 48, 40);
    const SceneGeometry geometry = SceneGeometry::build(scene);
    const std::vector<uint8_t> keep = pixelsSeeingNoDeltaSurfaceFirst(scene, geometry, 4);
    ASSERT_EQ(keep.size(), size_t(48 * 40));

    const RayCamera rc(scene.camera);
    size_t left = 0, wrong = 0;
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 48; ++x) {
            bool seesDelta = false;
            for (int k = 0; k < 16; ++k) {
                CameraSample cs;
                cs.filmX = (float(k % 4) + 0.5f) / 4.0f;
                cs.filmY = (float(k / 4) + 0.5f) / 4.0f;
                const PclRay ray = rc.generateRay(x, y, cs);
                const Vec3 o = rayOrigin(ray), d = rayDirection(ray);
                float nearest = 1e30f;
                bool nearestDelta = false;
                for (const Ball& b : balls) {
                    const Vec3 oc = o - b.c;
                    const float bb = dot(oc, d), cc = dot(oc, oc) - b.r * b.r, disc = bb * bb - cc;
                    if (disc < 0.0f) continue;
                    const float t = -bb - std::sqrt(disc);
                    if (t > 0.0f && t < nearest) {
                        nearest = t;
                        nearestDelta = b.delta;
                    }
                }
                seesDelta = seesDelta || nearestDelta;
            }
            left += seesDelta;
            wrong += (keep[size_t(y) * 48 + x] == 0) != seesDelta;
        }
    std::printf("[figure] specular pixel mask 48x40: %zu pixels left out, %zu differ from the closed form\n", left,
                wrong);
    EXPECT_GT(left, 100u);
    EXPECT_EQ(wrong, 0u);
}
