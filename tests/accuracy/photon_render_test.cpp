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
#include "geometry/scene_geometry.h"
#include "prep/plan.h"
#include "prep/projection_map.h"
#include "prep/scene_buffers.h"
#include "reference/path_tracer.h"
#include "render/photon_renderer.h"
#include "stages/device_fixture.h"

using namespace pcl;
using namespace pcl::accuracy;

namespace {

// A scene with everything the renderer needs, at the given size.
struct Prepared {
    Scene scene;
    std::unique_ptr<SceneGeometry> geometry;
    SceneBuffers buffers;
    LightPaths paths;
    RenderPlan plan;
};

std::unique_ptr<Prepared> prepare(const std::string& name, int width, int height) {
    auto p = std::make_unique<Prepared>();
    p->scene = loadSceneAt(name, width, height);
    p->geometry = std::make_unique<SceneGeometry>(SceneGeometry::build(p->scene));
    p->buffers = buildSceneBuffers(p->scene, *p->geometry);
    buildProjectionMaps(p->scene, *p->geometry, p->buffers);
    p->paths = classifyLightPaths(p->scene, *p->geometry, p->buffers);
    p->plan = makePlan(p->scene, p->paths);
    return p;
}

PhotonRenderResult render(const Prepared& p, PhotonRenderSettings s) {
    return renderPhotonMapped(test::testDevice(), p.scene, *p.geometry, p.buffers, p.plan, s);
}

void expectFinite(const PhotonRenderResult& r, const Image& img, const std::string& what) {
    size_t bad = 0;
    EXPECT_EQ(r.nonFiniteSamples, 0u) << what;
    EXPECT_TRUE(allFinite(img, &bad)) << what << ": pixel " << bad;
}

}  // namespace

// Final gathering at the test's settings (64 pixels wide, 2 passes × 4 stratified samples, 32
// gather rays, 8 light samples, 50k + 50k photons per pass: about a fortieth of the default
// render's work) against the 16k-sample path-traced references. Mean within 2 %; relMSE under
// 0.03 (measured 0.005-0.018).
// Not here, and why: cornell-spheres-point.json (mean +4.5 %). The path tracer cannot find paths
// on which a point light is seen through a specular surface (LS+D..., the caustics and what they
// light), so its reference lacks that light; half the excess is the caustic AOV itself.
// cornell-spheres.json is here since final_gather.cl leaves light reached through a specular
// bounce to the caustic map (causticMapRead): before, it counted the caustics twice (+3.1 %).
TEST(PhotonRenderAccuracy, FinalGatherMatchesEachShippedSceneReference) {
    ASSERT_TRUE(haveOpenImageIO()) << "the references are EXR";
    for (const std::string name :
         {"cornell-box.json", "cornell-spheres.json", "cornell-glossy.json", "motion-dof.json", "gltf-room.gltf"}) {
        Image ref = readImage(referencePath(name));
        auto p = prepare(name, ref.width, ref.height);
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

// The gather rays importance-sampled from 8×8 incident-flux histograms (--gather-importance 8):
// the same image in the mean (within 2 %), relMSE under the same bound (measured 0.0056 against
// 0.0046 with cosine sampling alone at these settings: no gain on the Cornell box).
TEST(PhotonRenderAccuracy, FinalGatherWithImportanceHistograms) {
    ASSERT_TRUE(haveOpenImageIO()) << "the references are EXR";
    Image ref = readImage(referencePath("cornell-box.json"));
    auto p = prepare("cornell-box.json", ref.width, ref.height);
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
        auto p = prepare(name, 32, 32);
        // One sphere seen from inside lights itself: the plan must build the global map.
        ASSERT_TRUE(p->plan.globalMap && p->plan.finalGather) << name;
        for (RenderMethod m : {RenderMethod::FinalGather, RenderMethod::DirectVisualisation, RenderMethod::Progressive,
                               RenderMethod::PathTracing}) {
            Image img;
            if (m == RenderMethod::PathTracing) {
                PathTracerSettings pt;
                pt.samplesPerPixel = 256;
                pt.seed = 2;
                pt.threads = 2;
                img = PathTracer(p->scene, *p->geometry, pt).render().resolve();
                EXPECT_TRUE(allFinite(img));
            } else {
                PhotonRenderSettings s;
                s.method = m;
                s.passes = m == RenderMethod::Progressive ? 8 : 2;
                s.gatherRays = 16;
                s.globalPhotons = 100000;
                s.seed = 5;
                PhotonRenderResult r = render(*p, s);
                img = r.film.resolve();
                expectFinite(r, img, name + " " + renderMethodName(m));
            }
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
    auto p = prepare(name, ref.width, ref.height);
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
    auto p = prepare("cornell-spheres.json", 24, 24);
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
