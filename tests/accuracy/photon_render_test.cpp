// The photon-mapping renderer against ground truth: every shipped scene's
// final-gather render against its path-traced reference (tests/data/), the furnace in every
// method against L = ρ/(1−ρ), and a per-pixel Z-test of progressive renders over 16 seeds.
// Small images and photon counts keep the whole file near two minutes on 2 cores under PoCL;
// what each test cuts is said beside it, and every figure is printed ("[figure]" lines).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <memory>

#include "accuracy/accuracy_common.h"
#include "common/prepared_render.h"
#include "common/test_scenes.h"
#include "core/math.h"
#include "geometry/scene_geometry.h"
#include "image/metrics.h"
#include "reference/light_tracer.h"
#include "render/render_settings.h"

using namespace pcl;
using namespace pcl::accuracy;

namespace {

using test::expectFinite;
using test::prepareFile;
using test::render;
using test::renderImage;

}  // namespace

// Final gathering at the test's settings (64 pixels wide, 2 passes × 4 stratified samples, 32
// gather rays, 8 light samples, 50k + 50k photons per pass: about a fortieth of the default
// render's work) against the 16k-sample path-traced references. Mean within 2 %; relMSE under
// 0.03 (measured 0.005-0.018).
// cornell-spheres-point.json is held below, to a tighter mean.
// cornell-spheres.json is here since final_gather.cl leaves light reached through a specular
// bounce to the caustic map (causticMapRead): before, it counted the caustics twice (+3.1 %).
TEST(PhotonRenderAccuracy, FinalGatherMatchesEachShippedSceneReference) {
    ASSERT_TRUE(haveOpenImageIO()) << "the references are EXR";
    for (const std::string name :
         {"cornell-box.json", "cornell-spheres.json", "cornell-glossy.json", "motion-dof.json", "gltf-room.gltf"}) {
        Image ref = readImage(referencePath(name));
        auto p = prepareFile(name, ref.width, ref.height);
        PhotonRenderSettings s;
        s.method = RenderMethod::FinalGather;
        s.passes = 2;
        s.strata = 2;
        s.gatherRays = 32;
        s.lightSamples = 8;
        s.globalPhotons = 50000;
        s.causticPhotons = 50000;
        s.seed = 3;
        PhotonRenderResult r = render(*p, s);
        Image img = r.film.resolve();
        ImageErrors e = compare(img, ref);
        std::printf("[figure] %s fg (64 wide, 2 passes x 4 spp, N 32, M 8, 50k+50k photons, %.1f s): %s\n",
                    name.c_str(), r.times.total, formatErrors(e).c_str());
        EXPECT_NEAR(e.meanRatio, 1.0, 0.02) << name;
        EXPECT_LT(e.relMse, 0.03) << name;
        expectFinite(r, img, name);
    }
}

// fg's bias where the map's blur shows through a mirror: the chrome ball of motion-dof reflects
// the floor beside and under it, where its own contact shadow lies. A gather ray from there that
// bounces off the ball's underside lands a few centimetres away, and the map's estimate blurs the
// lit floor into the shadow. Close gather hits count the path's length through mirrors
// (final_gather.cl): since, fg's squared relative bias against the 64-px reference at render's
// defaults (64×48, 2 seeds × 32 passes, 2026-12-04) fell from 2.5e-4 to 1.4e-4 (the reference's
// own relMSE 4.7e-5 included), and the darkest pixels' mean (the void behind the camera seen in
// the ball, lum < 0.02) from 1.39× to 1.11× the reference. Squared bias: the relMSE of the two
// renders' mean less its variance part, ((a−b)/2)². Here, 16 passes each: 2.6e-4 and 1.30× with
// close hits straight from the eye hit only, 1.5e-4 and 1.04× with them through mirrors, 9.4e-5
// and 1.04× since the ball's photons lie at shutter open (below); the bounds 2e-4 and 1.25×.
// The moving red ball lights the floor before it (the image's lowest quarter): its red read
// 0.983× the reference while the global map held the ball's photons where they landed, smeared
// along its path, and 0.997× since it keeps them where the ball sits at shutter open
// (kernels/shared/shutter_open.h); the bound is 1 %.
TEST(PhotonRenderAccuracy, MotionDofFgsBiasThroughTheChromeBallAndOnTheMovingBall) {
    ASSERT_TRUE(haveOpenImageIO()) << "the references are EXR";
    const std::string name = "motion-dof.json";
    const Image ref = readImage(referencePath(name));
    auto p = prepareFile(name, ref.width, ref.height, planSettingsFor("fg"));
    RenderRequest request;
    request.method = "fg";
    request.passes = 16;
    std::vector<Image> img;
    for (uint32_t seed : {1u, 2u}) {
        request.seed = seed;
        const PhotonRenderSettings s = resolveRenderSettings(request, p->plan, ref.width, ref.height).settings;
        const PhotonRenderResult r = render(*p, s);
        img.push_back(r.film.resolve());
        expectFinite(r, img.back(), name);
    }
    double bias = 0.0, dark = 0.0, darkRef = 0.0, red = 0.0, redRef = 0.0;
    const size_t foreground = size_t(ref.width) * size_t(ref.height - ref.height / 4) * 3;  // the lowest quarter
    for (size_t i = 0; i < ref.rgb.size(); ++i) {
        const double a = img[0].rgb[i], b = img[1].rgb[i], r = ref.rgb[i], m = 0.5 * (a + b);
        bias += ((m - r) * (m - r) - 0.25 * (a - b) * (a - b)) / (r * r + kRelMseEpsilon);
        const size_t px = i / 3 * 3;
        if (ref.rgb[px] + ref.rgb[px + 1] + ref.rgb[px + 2] < 3 * 0.02f) dark += m, darkRef += r;
        if (i >= foreground && i % 3 == 0) red += m, redRef += r;
    }
    bias /= double(ref.rgb.size());
    std::printf("[figure] %s fg at render's defaults, 64 wide, 2 seeds x 16 passes: squared relative bias %.3g, "
                "darkest pixels %.3f x the reference, the foreground's red %.4f x\n",
                name.c_str(), bias, dark / darkRef, red / redRef);
    EXPECT_LT(bias, 2.0e-4);
    EXPECT_LT(dark / darkRef, 1.25);
    EXPECT_NEAR(red / redRef, 1.0, 0.01);
}

// A point lamp's caustics and the light they spread (cornell-spheres-point): the reference holds
// them since render --method path adds the light tracer (tests/data/references.md; before, the
// path tracer alone lacked them and both methods read +4.5 % above it). fg at the settings above
// and progressive at 8 passes × 4 spp of 50k + 50k photons: mean within 1 % (measured +0.73 % and
// +0.07 %), relMSE under 0.03 (0.0068, 0.0041). The reference still lacks the light of
// L S ... S E paths (the caustic seen in the mirror ball or through the glass ball: ~0.5 % of the
// mean), which the photon maps hold.
TEST(PhotonRenderAccuracy, PointLampCausticsMatchTheLightTracedReference) {
    ASSERT_TRUE(haveOpenImageIO()) << "the references are EXR";
    const std::string name = "cornell-spheres-point.json";
    Image ref = readImage(referencePath(name));
    auto p = prepareFile(name, ref.width, ref.height);
    for (RenderMethod method : {RenderMethod::FinalGather, RenderMethod::Progressive}) {
        PhotonRenderSettings s;
        s.method = method;
        s.passes = method == RenderMethod::Progressive ? 8 : 2;
        s.strata = 2;
        s.gatherRays = 32;
        s.lightSamples = 8;
        s.globalPhotons = 50000;
        s.causticPhotons = 50000;
        s.seed = 3;
        PhotonRenderResult r = render(*p, s);
        Image img = r.film.resolve();
        ImageErrors e = compare(img, ref);
        std::printf("[figure] %s %s (64 wide, %u passes x 4 spp, 50k+50k photons, %.1f s) vs the light-traced "
                    "reference: %s\n",
                    name.c_str(), renderMethodName(method), s.passes, r.times.total, formatErrors(e).c_str());
        EXPECT_NEAR(e.meanRatio, 1.0, 0.01) << renderMethodName(method);
        EXPECT_LT(e.relMse, 0.03) << renderMethodName(method);
        expectFinite(r, img, name);
    }
}

// fg with caustic connections (--caustics connect) against the map alone, on the two caustic
// scenes: the same settings and photons, so the connections' caustic light must equal the map's
// in total (outside the pixels that see mirrors or glass first, where both read the map), and the
// image holds the reference as fg does (mean within 1 %, 2 % on cornell-spheres whose lamp edges 16
// samples per pixel leave aliased, as in the fg test above; relMSE under 0.03), judged where the
// reference is complete (compare --skip-specular-pixels: it lacks L S...S E light elsewhere).
// Measured (seed 5): caustic light -2.3 % / +0.7 %, means 0.9993 / 0.980 for both readers.
// motion-dof (its sun through the chrome ball, the lamp through the gold one; the red ball moves):
// the connections traced at each photon's shutter time; its caustic light is a seventh of
// cornell-spheres' and noisier, so 16 passes, and it lies along the floor beside the balls, where
// the map's k = 20 discs cross edges and read dark: connections +3.4 % here (+4.0 % at 4 passes;
// +1.5 % over every pixel with seed 9), bound 5 %. (That each record is traced at its own time
// is held by ConnectCaustics.ConnectionsInAMovingSceneAreTracedAtEachPhotonsTime.)
TEST(PhotonRenderAccuracy, CausticConnectionsCarryTheCausticMapsLight) {
    ASSERT_TRUE(haveOpenImageIO()) << "the references are EXR";
    for (const std::string name : {"cornell-spheres-point.json", "cornell-spheres.json", "motion-dof.json"}) {
        Image ref = readImage(referencePath(name));
        auto p = prepareFile(name, ref.width, ref.height);
        const std::vector<uint8_t> keep = pixelsSeeingNoDeltaSurfaceFirst(p->scene, *p->geometry);
        double caustic[2] = {0.0, 0.0};
        for (bool connect : {false, true}) {
            PhotonRenderSettings s;
            s.method = RenderMethod::FinalGather;
            s.passes = name == "motion-dof.json" ? 16 : 4;
            s.strata = 2;
            s.gatherRays = 16;
            s.lightSamples = 4;
            s.globalPhotons = 50000;
            s.causticPhotons = 50000;
            s.causticK = 20;
            s.aovs = true;
            s.causticConnections = connect;
            s.seed = 5;
            PhotonRenderResult r = render(*p, s);
            Image img = r.film.resolve(), c = r.aovs.caustic.resolve();
            for (size_t i = 0; i < keep.size(); ++i)
                if (keep[i]) caustic[connect] += double(c.rgb[3 * i]) + c.rgb[3 * i + 1] + c.rgb[3 * i + 2];
            ImageErrors e = compare(img, ref, keep);
            std::printf("[figure] %s fg caustics %s (64 wide, %u passes x 4 spp, 50k+50k photons, %.1f s, caustic "
                        "stage %.2f s) vs the reference without specular pixels: %s; caustic light %.4g\n",
                        name.c_str(), connect ? "connect" : "map", s.passes, r.times.total, r.times.caustic,
                        formatErrors(e).c_str(), caustic[connect]);
            EXPECT_NEAR(e.meanRatio, 1.0, name == "cornell-spheres.json" ? 0.02 : 0.01)
                << name << (connect ? " connect" : " map");
            EXPECT_LT(e.relMse, 0.03) << name << (connect ? " connect" : " map");
            expectFinite(r, img, name);
        }
        EXPECT_NEAR(caustic[1] / caustic[0], 1.0, name == "motion-dof.json" ? 0.05 : 0.03) << name;
    }
}

// fg's emitter samples (--emitter-strata): up to M × M eye paths per pixel and pass for the light
// collected before the diffuse hit, in the spans where a probe saw an emitter's edge (the lamp's
// rim; on cornell-glossy also its reflection in the Phong floor). Same settings with and without
// (64 wide, 2 passes × 16 spp, 4 gather rays, 2 light samples, 50k photons): the light the eye
// paths collect (the emitted AOV, summed over the image) agrees within 1 % (measured -0.5 %; over
// seeds 3, 7, 11 with 6 passes it read 2407/2404/2407 with the samples and 2419/2412/2406
// without: the same light, less noise), the mean within 1 % of the reference, and the RMSE falls
// to 0.37 × on cornell-box (16 × 16 in 34 pixels; bound 0.5) and 0.81 × on cornell-glossy, whose
// floor reflection holds 511 of the 4096 pixels, so M shrinks to 5 (bound 0.9).
TEST(PhotonRenderAccuracy, EmitterSamplesSharpenLampEdgesWithoutBias) {
    ASSERT_TRUE(haveOpenImageIO()) << "the references are EXR";
    for (const std::string name : {"cornell-box.json", "cornell-glossy.json"}) {
        Image ref = readImage(referencePath(name));
        auto p = prepareFile(name, ref.width, ref.height);
        double rmse[2] = {0, 0}, emitted[2] = {0, 0};
        for (uint32_t m : {0u, 16u}) {
            PhotonRenderSettings s;
            s.method = RenderMethod::FinalGather;
            s.passes = 2;
            s.strata = 4;
            s.gatherRays = 4;
            s.lightSamples = 2;
            s.globalPhotons = 50000;
            s.causticPhotons = 50000;
            s.emitterStrata = m;
            s.aovs = true;
            s.seed = 3;
            PhotonRenderResult r = render(*p, s);
            Image img = r.film.resolve(), em = r.aovs.emitted.resolve();
            ImageErrors e = compare(img, ref);
            const bool on = m > 0;
            rmse[on] = e.rmse;
            for (float v : em.rgb) emitted[on] += v;
            std::printf("[figure] %s fg, emitter strata %u (%ux%u in %u pixels; 64 wide, 2 passes x 16 spp, %.1f s): "
                        "%s; emitted light %.5g\n",
                        name.c_str(), m, r.emitterStrata, r.emitterStrata, r.emitterPixels, r.times.total,
                        formatErrors(e).c_str(), emitted[on]);
            EXPECT_NEAR(e.meanRatio, 1.0, 0.01) << name << " emitter strata " << m;
            if (on) {
                EXPECT_GT(r.emitterStrata, s.strata) << name;
                EXPECT_GT(r.emitterPixels, 0u) << name;
            }
            expectFinite(r, img, name);
        }
        EXPECT_NEAR(emitted[1] / emitted[0], 1.0, 0.01) << name;
        EXPECT_LT(rmse[1], (name == "cornell-box.json" ? 0.5 : 0.9) * rmse[0]) << name;
    }
}

// The gather rays importance-sampled from 8×8 incident-flux histograms (--gather-importance 8):
// the same image in the mean (within 2 %), relMSE under the same bound (measured 0.0056 against
// 0.0046 with cosine sampling alone at these settings: no gain on the Cornell box).
TEST(PhotonRenderAccuracy, FinalGatherWithImportanceHistograms) {
    ASSERT_TRUE(haveOpenImageIO()) << "the references are EXR";
    Image ref = readImage(referencePath("cornell-box.json"));
    auto p = prepareFile("cornell-box.json", ref.width, ref.height);
    PhotonRenderSettings s;
    s.passes = 2;
    s.strata = 2;
    s.gatherRays = 32;
    s.globalPhotons = 50000;
    s.histogramCells = 8;
    s.seed = 3;
    PhotonRenderResult r = render(*p, s);
    Image img = r.film.resolve();
    ImageErrors e = compare(img, ref);
    std::printf("[figure] cornell-box fg with 8x8 importance histograms: %s\n", formatErrors(e).c_str());
    EXPECT_NEAR(e.meanRatio, 1.0, 0.02);
    EXPECT_LT(e.relMse, 0.03);
    expectFinite(r, img, "importance");
}

// The furnace (L = 1 and 4 everywhere) in every method, 32×32: mean within 1 %.
TEST(PhotonRenderAccuracy, FurnaceInEveryMethod) {
    for (double rho : {0.5, 0.8}) {
        const std::string name = rho < 0.7 ? "furnace-0.5.json" : "furnace-0.8.json";
        const double expected = furnaceRadiance(rho);
        auto p = prepareFile(name, 32, 32);
        // One sphere seen from inside lights itself: the plan must build the global map.
        ASSERT_TRUE(p->plan.globalMap && p->plan.finalGather) << name;
        for (RenderMethod m : {RenderMethod::FinalGather, RenderMethod::DirectVisualisation, RenderMethod::Progressive,
                               RenderMethod::PathTracing}) {
            PhotonRenderSettings s;
            s.passes = m == RenderMethod::Progressive ? 8 : 2;
            s.gatherRays = 16;
            s.globalPhotons = 100000;
            s.seed = 5;
            const Image img = renderImage(*p, m, s, 256, 2, name);
            double mean = meanValue(img);
            std::printf("[figure] furnace rho %.1f, %s: mean %.5f expected %.5f (%+.3f%%)\n", rho, renderMethodName(m),
                        mean, expected, 100.0 * (mean / expected - 1.0));
            EXPECT_NEAR(mean / expected, 1.0, 0.01) << name << " " << renderMethodName(m);
        }
    }
}

// Progressive photon mapping is consistent: its bias shrinks with the radius. Over 16 seeds
// (independent photons and eye samples) of cornell-box at 32×32, 12 passes each, the per-pixel
// mean must agree with the reference (2×2-averaged) within |z| < 4 on at least 99.5 % of the
// pixels (Student's t with 15 degrees of freedom passes 99.88 % of pure noise).
// Why k0 = 5 photons per first disc (the renderer's default is 20): with α = 2/3 the bias falls
// as r² ∝ N^(α−1) and the noise as N^(−α/2), both as N^(−1/3), so the z of the boundary bias at
// the box's edges and corners does not shrink with passes; it is set by r_0 alone. The test
// therefore asks that the first radius's bias sit under the noise, and k0 = 5 makes it so. With
// the default 20 it does not: 12 of 1024 pixels fail (98.8 %; the dark corners and the block's
// edges, 5-30 % too dark), which is how this test fails on a too-large radius.
// Measured with k0 = 5: 3 fail (a lamp-edge pixel whose 192 samples all hit the lamp, and two
// pixels beside the tall block's edge). The radius schedule r²_{i+1} = r²_i (i+α)/(i+1) is held
// to its closed form after n passes, r²_{n−1} / r²_0 = Γ(n+α) / (Γ(1+α) Γ(n+1)) (1e-5 relative:
// float radii).
// Cut for time: 32×32 pixels, 50k photons per pass.
TEST(PhotonRenderAccuracy, ProgressiveZTestOverSixteenSeeds) {
    ASSERT_TRUE(haveOpenImageIO()) << "the references are EXR";
    const std::string name = "cornell-box.json";
    Image ref = boxDownsample(readImage(referencePath(name)), 2);
    auto p = prepareFile(name, ref.width, ref.height);
    std::vector<Image> runs;
    double seconds = 0.0;
    const uint32_t kPasses = 12;
    for (uint64_t seed = 1; seed <= 16; ++seed) {
        PhotonRenderSettings s;
        s.method = RenderMethod::Progressive;
        s.passes = kPasses;
        s.globalPhotons = 50000;
        s.causticPhotons = 50000;
        s.seed = 1000 + seed;
        s.progressiveK0 = 5.0f;
        PhotonRenderResult r = render(*p, s);
        runs.push_back(r.film.resolve());
        expectFinite(r, runs.back(), "seed " + std::to_string(seed));
        seconds += r.times.total;
        if (seed == 1) {
            const double n = kPasses, alpha = s.alpha;  // the last pass is pass n − 1 (passes count from 0)
            const double shrink = std::exp(std::lgamma(n + alpha) - std::lgamma(1 + alpha) - std::lgamma(n + 1));
            std::printf("[figure] progressive radius %.4g -> %.4g over %u passes (r²_n/r²_0 %.6f, closed form %.6f)\n",
                        r.firstRadius, r.lastRadius, kPasses,
                        double(r.lastRadius) * r.lastRadius / (double(r.firstRadius) * r.firstRadius), shrink);
            EXPECT_NEAR(double(r.lastRadius) * r.lastRadius / (double(r.firstRadius) * r.firstRadius) / shrink, 1.0,
                        1e-5);
        }
    }
    ZTestResult z = perPixelZTest(runs, ref, 4.0);
    Image mean(ref.width, ref.height);
    for (const Image& run : runs)
        for (size_t i = 0; i < mean.rgb.size(); ++i) mean.rgb[i] += run.rgb[i] / runs.size();
    std::printf("[figure] %s progressive, 16 seeds x %u passes (%.1f s): %s; mean of runs vs reference: %s\n",
                name.c_str(), kPasses, seconds, formatZTest(z).c_str(), formatErrors(compare(mean, ref)).c_str());
    for (size_t i : z.failed) {
        double m = 0, r = ref.at(int(i % ref.width), int(i / ref.width)).x;
        for (const Image& run : runs) m += run.at(int(i % ref.width), int(i / ref.width)).x / runs.size();
        std::printf("[figure]   failed pixel (%zu, %zu): red mean %.4g, reference %.4g\n", i % ref.width, i / ref.width,
                    m, r);
    }
    EXPECT_GE(z.passFraction(), 0.995);
    EXPECT_EQ(z.nonFinite, 0u);
}

// The maps' search structure changes the speed, not the photons found (check --stage knn proves
// the same neighbours; the sweep charts the speed): a render with the hash grid equals the
// kd-tree's in each method that searches a map (fg here reads the full estimate). Measured: fg
// and direct bit for bit; progressive within 1.9e-7 relative in a tenth of the values, since it
// sums every photon in its disc (up to PCL_KNN_MAX_K) in an order that follows the structure's
// traversal. Bound: 1e-6 relative.
TEST(PhotonRenderAccuracy, HashGridAndKdTreeRenderTheSameImage) {
    auto p = prepareFile("cornell-spheres.json", 24, 24);
    for (RenderMethod m : {RenderMethod::DirectVisualisation, RenderMethod::FinalGather, RenderMethod::Progressive}) {
        PhotonRenderSettings s;
        s.method = m;
        s.passes = 2;
        s.gatherRays = 8;
        s.gatherSource = GatherSource::Estimate;
        s.globalPhotons = 20000;
        s.causticPhotons = 20000;
        s.seed = 5;
        Image kd = render(*p, s).film.resolve();
        s.structure = KnnStructure::HashGrid;
        Image grid = render(*p, s).film.resolve();
        ASSERT_EQ(kd.rgb.size(), grid.rgb.size());
        size_t differ = 0;
        double worst = 0;
        for (size_t i = 0; i < kd.rgb.size(); ++i) {
            differ += kd.rgb[i] != grid.rgb[i];
            worst = std::max(worst, std::abs(double(kd.rgb[i]) - grid.rgb[i]) / std::max(1e-6f, std::abs(kd.rgb[i])));
        }
        std::printf("[figure] %s: %zu of %zu values differ between kd-tree and hash grid, by at most %.3g relative\n",
                    renderMethodName(m), differ, kd.rgb.size(), worst);
        EXPECT_LT(worst, 1e-6) << renderMethodName(m);
    }
}

// Radiance seen from inside glass (issue 16): radiance crossing from index η_i into η_t scales
// by (η_t/η_i)², so a camera inside glass (η = 1.5) sees the world outside 2.25 times brighter
// (pbrt-v4's DielectricBxDF in radiance mode). The camera sits at the centre of a glass sphere
// (radius 1, ρs = 1), so every camera ray leaves it at normal incidence (F = ((η−1)/(η+1))² =
// 0.04), and looks at a diffuse wall (ρ = 0.5, z = −3) lit by a directional light at 60° with
// E = π on the wall: L_wall = ρE/π = 0.5. Refracted out with 1 − F, or reflected back and out
// after two more internal reflections (F², F⁴, ...; the far side sees nothing):
// L = η² L_wall (1 − F)/(1 − F²) = η² L_wall/(1 + F) = 1.0817. Without the η² factor: 0.4808.
// The light, the sphere's shadow (x > 3.2 on the wall's plane) and its caustic are away from
// the view (|x|, |y| < 0.53). Not in the closed form: light reflected by the sphere's outside onto
// the wall (≈ E F(60°)/36 ≈ +0.5 %, in the photon methods' caustic map only: the path tracer
// cannot find a delta light through a delta surface) and the wall lighting itself via the
// sphere (< 0.3 %).
TEST(PhotonRenderAccuracy, RadianceSeenFromInsideGlassScalesByEtaSquared) {
    using namespace test_scenes;
    const float eta = 1.5f, rho = 0.5f;
    Scene scene;
    const int glass = addMaterial(scene, Vec3(0.0f), Vec3(1.0f), SpecularKind::Dielectric);
    scene.materials[glass].ior = eta;
    const int wall = addMaterial(scene, Vec3(rho));
    addSphere(scene, Vec3(0.0f), 1.0f, glass);
    addQuad(scene, Vec3(-1.5f, -1.5f, -3.0f), Vec3(3.0f, 0.0f, 0.0f), Vec3(0.0f, 3.0f, 0.0f), wall);  // faces +z
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = normalize(Vec3(std::sqrt(3.0f), 0.0f, -1.0f));  // 60° off the wall's normal
    sun.irradiance = Vec3(2.0f * kPi);                              // E = 2π cos 60° = π on the wall
    scene.lights.push_back(sun);
    scene.camera.position = Vec3(0.0f);
    scene.camera.lookAt = Vec3(0.0f, 0.0f, -1.0f);
    scene.camera.vfovDegrees = 20.0f;
    scene.camera.width = scene.camera.height = 16;
    auto p = test::prepare(scene);

    const double F = std::pow((eta - 1.0) / (eta + 1.0), 2.0);
    const double expected = double(eta) * eta * rho / (1.0 + F);
    for (RenderMethod m : {RenderMethod::PathTracing, RenderMethod::FinalGather, RenderMethod::DirectVisualisation,
                           RenderMethod::Progressive}) {
        PhotonRenderSettings s;
        s.strata = m == RenderMethod::Progressive ? 4 : 8;  // 128 samples per pixel in each method
        s.passes = m == RenderMethod::Progressive ? 8 : 2;
        s.gatherRays = 16;
        s.globalPhotons = 200000;
        s.causticPhotons = 50000;
        s.globalK = 200;
        s.seed = 7;
        const Image img = renderImage(*p, m, s, 256, 7, "inside glass");
        double worst = 0.0;
        for (float v : img.rgb) worst = std::max(worst, std::abs(v / expected - 1.0));
        const double mean = meanValue(img);
        std::printf("[figure] inside glass, %s: mean %.5f expected %.5f (%+.2f%%), worst pixel %.2f%%\n",
                    renderMethodName(m), mean, expected, 100.0 * (mean / expected - 1.0), 100.0 * worst);
        // Mean: within 3 %. The photon methods measure +1.5..1.8 %: the light the sphere's
        // outside sends onto the wall (with the caustic map left out, fg and progressive measure
        // −0.2 %); the path tracer −0.03 %. Per pixel: 128 or 256 samples of which 4 % reflect
        // to nothing give 1.8 % (1.25 %) noise; worst of 256 pixels measured 6.1-6.9 % (4.5 %
        // path); direct visualisation adds its kNN noise (200 photons: 13.6 %). Bounds 8 % path,
        // 12 % fg and progressive, 20 % direct. Without the η² factor every method is −55 %.
        EXPECT_NEAR(mean / expected, 1.0, 0.03) << renderMethodName(m);
        const double perPixel = m == RenderMethod::PathTracing           ? 0.08
                                : m == RenderMethod::DirectVisualisation ? 0.20
                                                                         : 0.12;
        EXPECT_LT(worst, perPixel) << renderMethodName(m);
    }
}
