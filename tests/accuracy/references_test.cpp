// Ground truth itself: every shipped scene has a reference (render --method path) in
// tests/data/, finite, at the size the accuracy tests render; the furnace scenes' references
// and fresh path-traced renders give L = ρ/(1−ρ) within 1 %; a short fresh render agrees with
// each stored reference per pixel (a stale reference after a scene edit fails here, not in a
// photon test).
#include <gtest/gtest.h>
#include "common/optional_feature.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "accuracy/accuracy_common.h"
#include "geometry/scene_geometry.h"
#include "render/path_render.h"

using namespace pcl;
using namespace pcl::accuracy;

namespace {

// What the references are made with (`render --method path`): the path tracer, plus the light
// tracer where a delta light shines through mirrors or glass (render/path_render.h).
Image pathTraced(const Scene& scene, int spp, uint64_t seed) {
    SceneGeometry geometry = SceneGeometry::build(scene);
    PathRenderSettings settings;
    settings.samples = static_cast<uint32_t>(spp);
    settings.seed = seed;
    settings.threads = 2;
    PathRenderResult r = renderPathTraced(scene, geometry, settings);
    EXPECT_EQ(r.discarded, 0u);
    return r.film.resolve();
}

}  // namespace

// Every scene file in scenes/media/ is in mediaScenes(), so none lacks its reference tests.
TEST(References, EveryMediaSceneIsListed) {
    const std::filesystem::path dir = std::filesystem::path(PHOTONCL_SOURCE_DIR) / "scenes" / "media";
    size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        if (e.path().extension() != ".json") continue;
        ++files;
        const std::string name = "media/" + e.path().filename().string();
        const auto listed = mediaScenes();
        EXPECT_NE(std::find(listed.begin(), listed.end(), name), listed.end()) << name << " is not in mediaScenes()";
        EXPECT_TRUE(loadScene(scenePath(name)).hasMedia()) << name;
    }
    EXPECT_EQ(files, mediaScenes().size());
}

TEST(References, EveryShippedSceneHasAFiniteReference) {
    PCL_REQUIRE_FEATURE(haveOpenImageIO(), "OpenImageIO (the references are EXR)");
    for (const std::string& name : pathTracedScenes()) {
        ASSERT_TRUE(std::filesystem::exists(referencePath(name)))
            << referencePath(name) << " missing: run scripts/make_references.py";
        ImageMetadata meta;
        Image ref = readImage(referencePath(name), &meta);
        size_t bad = 0;
        EXPECT_TRUE(allFinite(ref, &bad)) << name << ": pixel " << bad << " is not finite";
        // make_references.py records the samples per pixel (an integer attribute, by oiiotool).
        EXPECT_GE(meta.samples, 4096) << name;
        EXPECT_EQ(meta.method, "path") << name;
        Scene scene = loadScene(scenePath(name));
        // The reference keeps the camera's aspect ratio (render --width W).
        EXPECT_EQ(ref.height, std::max(1, ref.width * scene.camera.height / scene.camera.width)) << name;
        EXPECT_GT(meanValue(ref), 0.0) << name;
    }
}

// The closed form: L = ρ/(1−ρ) = 1 and 4. The stored references (4096 samples per pixel) and a
// fresh 512-sample render of the same scene file, each mean within 1 %; the fresh render's mean
// has a standard error of ~0.05 % (ρ 0.5) and ~0.15 % (ρ 0.8).
TEST(References, FurnaceMatchesTheClosedForm) {
    for (double rho : {0.5, 0.8}) {
        std::string name = rho < 0.7 ? "furnace-0.5.json" : "furnace-0.8.json";
        double expected = furnaceRadiance(rho);
        Scene scene = loadSceneAt(name, 32, 32);
        Image fresh = pathTraced(scene, 512, 11);
        double mean = meanValue(fresh);
        std::printf("[figure] furnace rho %.1f, path tracer 512 spp: mean %.5f expected %.5f (%+.3f%%)\n", rho, mean,
                    expected, 100.0 * (mean / expected - 1.0));
        EXPECT_NEAR(mean / expected, 1.0, 0.01);
        EXPECT_TRUE(allFinite(fresh));
        if (haveOpenImageIO()) {
            Image ref = readImage(referencePath(name));
            double refMean = meanValue(ref);
            std::printf("[figure] furnace rho %.1f, stored reference: mean %.5f (%+.3f%%)\n", rho, refMean,
                        100.0 * (refMean / expected - 1.0));
            EXPECT_NEAR(refMean / expected, 1.0, 0.01);
        }
    }
}

// A fresh render by the references' own method (path tracer, plus the light tracer where the
// scene needs it) at the reference's size, per pixel: 16 independent runs of 8
// samples (seeds 101-116) against the stored reference by a Z-test on 2×2 pixel blocks, |z| < 4
// (Student's t with 15 degrees of freedom passes 99.88 % of pure noise; the reference's own noise
// is a thirtieth of the runs' and left out); at least 98.5 % of the blocks must pass (measured
// 98.8 % on gltf-room to 100 %). cornell-spheres is the exception: its walls are lit through the
// glass ball by paths that hit the lamp rarely (fireflies), so at 8 samples a run's mean is
// heavy-tailed, the 16 runs' spread underestimates the noise and most blocks that missed the
// fireflies read too dark (2×2 blocks: 81 % pass although a 4096-sample render agrees with the
// reference within 1-3 % in every 8×8 block). Its blocks are 8×8 and the bound 92 % (measured
// 95.3 %). Also the mean ratio within 2 % (the 128-sample mean over ~4000 pixels has a standard
// error of 0.2-0.7 %). The glass ball moved by 3 cm (a twentieth of the box) keeps the mean
// (0.998) and fails: 89.1 % of the 8×8 blocks pass; the mirror ball of cornell-spheres-point moved
// by 3 cm fails with 94.3 % of the 2×2 blocks.
TEST(References, FreshPathTracedRenderAgreesWithEachReference) {
    PCL_REQUIRE_FEATURE(haveOpenImageIO(), "OpenImageIO (the references are EXR)");
    for (const std::string& name : pathTracedScenes()) {
        Image ref = readImage(referencePath(name));
        Scene scene = loadSceneAt(name, ref.width, ref.height);
        std::vector<Image> runs;
        Image mean(ref.width, ref.height);
        for (uint64_t seed = 101; seed <= 116; ++seed) {
            runs.push_back(pathTraced(scene, 8, seed));
            EXPECT_TRUE(allFinite(runs.back())) << name << " seed " << seed;
            for (size_t i = 0; i < mean.rgb.size(); ++i) mean.rgb[i] += runs.back().rgb[i] / 16.0f;
        }
        ImageErrors e = compare(mean, ref);
        // cornell-spheres: heavy-tailed (see above), so its blocks are 8×8 and the bound lower. So
        // are the media scenes: cornell-fog has the same glass ball (and the fog scatters its
        // rare lamp paths everywhere); hazy-room's spot is a point light in haze, and next-event
        // estimation toward a point from scattering events near it has unbounded variance
        // (∫ r⁻⁴ r² dr diverges at the light; equiangular sampling would fix it): at 2×2 blocks
        // 94 % and 95 % pass with the means at 1.000 and 0.987.
        // The courtyard's sun is one texel of the sky: its caustic under the glass ball comes only
        // from paths that leave the glass toward that texel, rare and bright.
        const bool heavyTailed = name == "cornell-spheres.json" || name.rfind("media/", 0) == 0 ||
                                 name.rfind("courtyard/", 0) == 0;
        const int block = heavyTailed ? 8 : 2;
        const double required = heavyTailed ? 0.92 : 0.985;
        std::vector<Image> blocks;
        for (const Image& run : runs) blocks.push_back(boxDownsample(run, block));
        ZTestResult z = perPixelZTest(blocks, boxDownsample(ref, block), 4.0);
        std::printf("[figure] %s: path tracer 16 x 8 spp vs reference: %s; %dx%d blocks %s (bound %.1f%%)\n",
                    name.c_str(), formatErrors(e).c_str(), block, block, formatZTest(z).c_str(), 100 * required);
        EXPECT_NEAR(e.meanRatio, 1.0, 0.02) << name;
        EXPECT_GE(z.passFraction(), required) << name;
        EXPECT_EQ(z.nonFinite, 0u) << name;
    }
}

// The 256×256 references of the equal-time comparisons (tests/data/references-256.md, made by
// hand with other seeds and sample counts) against the 64-wide ones, 4×4-averaged: finite, the
// camera's aspect, the image means within 0.5 % (each mean's standard error is under 0.1 %),
// and the 64×64 images within a relMSE of 2e-3 (the two references' own noise: measured 5e-5 to
// 4.5e-4; hazy-room's own bound below). cornell-box's 256 reference held to cornell-glossy's
// small one (the floor glossy instead of diffuse) gives relMSE 0.018 and mean 1.024, to
// cornell-spheres' 0.11: both fail.
TEST(References, EqualTimeReferencesAgreeWithTheSmallOnes) {
    PCL_REQUIRE_FEATURE(haveOpenImageIO(), "OpenImageIO (the references are EXR)");
    const std::filesystem::path data = std::filesystem::path(PHOTONCL_SOURCE_DIR) / "tests" / "data";
    size_t found = 0;
    std::vector<std::string> scenes = referencedScenes();
    for (const std::string& name : texturedScenes()) scenes.push_back(name);
    for (const std::string& name : mediaScenes()) scenes.push_back(name);
    // sky-spheres has no 64-px photoncl reference: its 256² one is held to Mitsuba's render.
    scenes.push_back("sky-spheres.json");
    for (const std::string& name : scenes) {
        const std::string stem = std::filesystem::path(name).stem().string();
        const std::filesystem::path big = data / ("ref256-" + stem + ".exr");
        if (!std::filesystem::exists(big)) continue;
        ++found;
        const Image ref256 = readImage(big.string());
        size_t bad = 0;
        EXPECT_TRUE(allFinite(ref256, &bad)) << big << ": pixel " << bad;
        const Scene scene = loadScene(scenePath(name));
        EXPECT_EQ(ref256.width, 256) << big;
        EXPECT_EQ(ref256.height, 256 * scene.camera.height / scene.camera.width) << big;
        std::filesystem::path smallPath = referencePath(name);
        if (!std::filesystem::exists(smallPath)) smallPath = data / ("mitsuba-" + stem + ".exr");
        const Image small = readImage(smallPath.string());
        const ImageErrors e = compare(boxDownsample(ref256, 4), small);
        std::printf("[figure] %s 4x4-averaged vs %s: %s\n", big.filename().c_str(), smallPath.filename().c_str(),
                    formatErrors(e).c_str());
        EXPECT_NEAR(e.meanRatio, 1.0, 0.005) << big;
        // hazy-room: the 64-px reference's own relMSE is 4.4e-3 (the spot light's fireflies in
        // the haze), so the pair reads 3.75e-3; its 512-spp trial halves read 8.6e-3.
        EXPECT_LT(e.relMse, name == "media/hazy-room.json" ? 6e-3 : 2e-3) << big;
    }
    EXPECT_EQ(found, 10u) << "tests/data/references-256.md lists ten 256-wide references (all but the furnaces, "
                             "whose answer is exact)";
}
