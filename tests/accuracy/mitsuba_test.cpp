// Independent ground truth: the shipped scenes that Mitsuba 3 expresses exactly, rendered by
// Mitsuba's path tracer (tests/data/mitsuba-<scene>.exr, scripts/make_mitsuba_references.py,
// table in tests/data/references-mitsuba.md). Each file holds the mean of 16 independent chunks
// and, as layers, its per-pixel standard error (`sem`: per channel; `semsum`: of R+G+B). Held
// against them: the CPU reference path tracer (per-pixel Z-test using both sides' noise), the
// stored path-traced references tests/data/ref-*.exr, and every photon method. Every figure is
// printed ("[figure]" lines). A bug shared by photoncl's path tracer and its photon kernels
// cannot hide here the way it can against references made by photoncl itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>

#include "accuracy/accuracy_common.h"
#include "common/prepared_render.h"
#include "geometry/scene_geometry.h"
#include "image/film.h"
#include "reference/light_tracer.h"
#include "reference/path_tracer.h"

using namespace pcl;
using namespace pcl::accuracy;

namespace {

// The scenes scripts/mitsuba_scene.py converts (the others are refused there, with the reason:
// glossy Phong lobes, motion, glTF, spot lights), among them cornell-fog (participating media:
// Mitsuba's volpath with its homogeneous medium and hg phase function).
const std::vector<std::string>& mitsubaScenes() {
    static const std::vector<std::string> names = {"cornell-box.json",           "cornell-spheres.json",
                                                   "cornell-spheres-point.json", "furnace-0.5.json",
                                                   "furnace-0.8.json",           "media/cornell-fog.json"};
    return names;
}

struct MitsubaReference {
    Image mean;
    Image sem;     // per channel standard error of `mean`
    Image semSum;  // standard error of R+G+B (all three channels)
    // The image mean's standard error (pixels independent): sqrt(Σ sem²) / values.
    double meanSem() const {
        double s = 0;
        for (float v : sem.rgb) s += double(v) * v;
        return std::sqrt(s) / double(sem.rgb.size());
    }
    // R channel: the variance of R+G+B, as perPixelZTest takes it.
    Image sumVariance() const {
        Image v(semSum.width, semSum.height);
        for (size_t i = 0; i < v.rgb.size(); ++i) v.rgb[i] = semSum.rgb[i] * semSum.rgb[i];
        return v;
    }
};

std::string mitsubaPath(const std::string& sceneName) {
    return (std::filesystem::path(PHOTONCL_SOURCE_DIR) / "tests" / "data" /
            ("mitsuba-" + std::filesystem::path(sceneName).stem().string() + ".exr"))
        .string();
}

MitsubaReference readMitsuba(const std::string& sceneName) {
    const std::string path = mitsubaPath(sceneName);
    MitsubaReference r;
    r.mean = readImage(path);
    r.sem = readImageLayer(path, "sem");
    r.semSum = readImageLayer(path, "semsum");
    return r;
}

// R+G+B of pixel i.
double channelSum(const Image& img, size_t i) {
    return double(img.rgb[3 * i]) + img.rgb[3 * i + 1] + img.rgb[3 * i + 2];
}

// Relative differences of b×b block means (R+G+B) between a render and the reference, over
// blocks whose reference is not black: the worst, and the fraction within `within`.
struct BlockErrors {
    double worst = 0;
    int worstIndex = -1;
    double fractionWithin = 0;
};

BlockErrors blockErrors(const Image& img, const Image& ref, int block, double within) {
    Image a = boxDownsample(img, block), r = boxDownsample(ref, block);
    BlockErrors b;
    size_t counted = 0, inside = 0;
    for (size_t i = 0; i < r.pixelCount(); ++i) {
        double rv = channelSum(r, i);
        if (!(rv > 1e-3)) continue;
        double e = std::abs(channelSum(a, i) - rv) / rv;
        ++counted;
        inside += e <= within;
        if (!(e <= b.worst)) {  // NaN counts as worst
            b.worst = e;
            b.worstIndex = int(i);
        }
    }
    b.fractionWithin = counted ? double(inside) / counted : 0;
    return b;
}

// Samples per pixel of each Mitsuba reference (scripts/make_mitsuba_references.py).
double mitsubaSamples(const std::string& name) {
    return name.rfind("furnace", 0) == 0 ? 8192 : name.rfind("media/", 0) == 0 ? 4096 : 16384;
}

}  // namespace

// Every Mitsuba reference is there, finite, at the size of the photoncl reference, with a
// positive standard error; the furnaces' at the closed form.
TEST(MitsubaReferences, EveryConvertibleSceneHasAReferenceWithItsNoise) {
    ASSERT_TRUE(haveOpenImageIO()) << "the references are EXR";
    for (const std::string& name : mitsubaScenes()) {
        ASSERT_TRUE(std::filesystem::exists(mitsubaPath(name)))
            << mitsubaPath(name) << " missing: run scripts/make_mitsuba_references.py";
        MitsubaReference m = readMitsuba(name);
        Image ref = readImage(referencePath(name));
        EXPECT_EQ(m.mean.width, ref.width) << name;
        EXPECT_EQ(m.mean.height, ref.height) << name;
        EXPECT_TRUE(allFinite(m.mean) && allFinite(m.sem) && allFinite(m.semSum)) << name;
        EXPECT_GT(meanValue(m.mean), 0.0) << name;
        EXPECT_GT(meanValue(m.semSum), 0.0) << name;
        std::printf("[figure] %s: Mitsuba mean %.5f +- %.2g\n", name.c_str(), meanValue(m.mean), m.meanSem());
        // The furnace checks the conversion itself: every wall point has L = ρ/(1−ρ) (1 and 4).
        // Mitsuba's means measured 1.00006 and 3.99954 (standard errors 0.004 % and 0.014 %);
        // bound 0.1 %, which an emitter scaled by 1/π or a lost bounce would exceed many times.
        if (name.rfind("furnace", 0) == 0) {
            double rho = name == "furnace-0.5.json" ? 0.5 : 0.8;
            EXPECT_NEAR(meanValue(m.mean) / furnaceRadiance(rho), 1.0, 0.001) << name;
        }
    }
}

namespace {

// The reference path tracer at 256 samples per pixel (64 runs of 4, seed 7), once per scene:
// the mean, and the per-sample variance of R+G+B per pixel. That variance is the larger of the
// runs' own sample variance and Mitsuba's (from its 16 chunks, × its samples per pixel): where a
// few rare paths carry much of a pixel (cornell-spheres: light refracted through the glass ball
// to the lamp, found only by BSDF sampling), 256 samples mostly miss them, so their own variance
// and their mean both come out low together, while Mitsuba's 16 × 1024 samples do see them. With
// the runs' own variance alone, 9 % of cornell-spheres' pixels fail |z| < 3.5, every one of them
// below Mitsuba, while the image mean is 0.3 % above it: the skew of a small sample, not a bias
// (the stored 32768-sample reference agrees per pixel, below). The other scenes pass either way.
struct PathTraced {
    Image mean;
    std::vector<double> sampleVariance;  // per pixel, of R+G+B of one sample
    double meanRatioSe = 0;              // standard error of the image mean, from the runs
};

const PathTraced& pathTraced(const std::string& name, const MitsubaReference& m) {
    static std::map<std::string, PathTraced> cache;
    auto found = cache.find(name);
    if (found != cache.end()) return found->second;
    constexpr int kRuns = 64, kSamplesPerRun = 4;
    Scene scene = loadSceneAt(name, m.mean.width, m.mean.height);
    SceneGeometry geometry = SceneGeometry::build(scene);
    std::vector<Image> runs;
    for (int run = 0; run < kRuns; ++run) {
        PathTracerSettings s;
        s.samplesPerPixel = kSamplesPerRun;
        s.firstSample = run * kSamplesPerRun;
        s.seed = 7;
        s.threads = 2;
        PathTracerStats stats;
        runs.push_back(PathTracer(scene, geometry, s).render(&stats).resolve());
        EXPECT_EQ(stats.discardedSamples, 0u) << name;
    }
    PathTraced pt;
    pt.mean = Image(m.mean.width, m.mean.height);
    for (const Image& r : runs)
        for (size_t i = 0; i < r.rgb.size(); ++i) pt.mean.rgb[i] += r.rgb[i] / float(kRuns);
    const double mitsubaSpp = mitsubaSamples(name);
    for (size_t i = 0; i < pt.mean.pixelCount(); ++i) {
        double mu = channelSum(pt.mean, i), ss = 0;
        for (const Image& r : runs) ss += (channelSum(r, i) - mu) * (channelSum(r, i) - mu);
        double own = ss / (kRuns - 1.0) * kSamplesPerRun;
        double mitsuba = double(m.semSum.rgb[3 * i]) * m.semSum.rgb[3 * i] * mitsubaSpp;
        pt.sampleVariance.push_back(std::max(own, mitsuba));
    }
    double mu = meanValue(pt.mean), ss = 0;
    for (const Image& r : runs) ss += (meanValue(r) - mu) * (meanValue(r) - mu);
    pt.meanRatioSe = std::sqrt(ss / (kRuns - 1.0) / kRuns);
    return cache[name] = std::move(pt);
}

// Per-pixel z of R+G+B between two estimates with known variances of their means.
struct PixelZ {
    size_t pixels = 0, passed = 0;
    double maxAbsZ = 0;
    double passFraction() const { return pixels ? double(passed) / pixels : 0; }
};

PixelZ pixelZ(const Image& a, const std::vector<double>& varA, const Image& b, const Image& semSumB, double threshold) {
    PixelZ z;
    for (size_t i = 0; i < a.pixelCount(); ++i) {
        double d = channelSum(a, i) - channelSum(b, i);
        double var = varA[i] + double(semSumB.rgb[3 * i]) * semSumB.rgb[3 * i];
        // A pixel without noise on either side (black outside the box) must agree to half-float rounding.
        double az = var > 0 ? std::abs(d) / std::sqrt(var)
                            : (std::abs(d) <= 1e-3 * std::abs(channelSum(b, i)) ? 0 : HUGE_VAL);
        ++z.pixels;
        z.passed += az < threshold;  // NaN fails
        if (!(az <= z.maxAbsZ)) z.maxAbsZ = az;
    }
    return z;
}

}  // namespace

// The reference path tracer against Mitsuba, per pixel: 256 samples (pathTraced), z = (mean −
// Mitsuba) / sqrt(var/256 + SE_mitsuba²) on R+G+B. For Gaussian pixel errors P(|z| < 3.5) =
// 0.9995; the errors here are skewed (Russian roulette from the 3rd bounce leaves 1 in 8
// furnace paths to carry the rest; rare caustic paths in cornell-spheres), so a pixel that drew
// few of the rare paths has both a low mean and a low sample variance: furnace-0.5 fails 7 of
// 1024 pixels, all below Mitsuba (2.82 against 3.00), the largest |z| 6.44. Bounds: |z| < 3.5 on
// at least 99 % of the pixels and no pixel beyond |z| = 10 (a change confined to a few pixels,
// such as a sphere's edge moved by a pixel, shows as a few huge |z|, not as a pass-rate drop);
// the image mean within 4 of its standard errors (both sides) and within 1 %.
TEST(MitsubaReferences, PathTracerAgreesPerPixel) {
    ASSERT_TRUE(haveOpenImageIO()) << "the references are EXR";
    for (const std::string& name : mitsubaScenes()) {
        MitsubaReference m = readMitsuba(name);
        const PathTraced& pt = pathTraced(name, m);
        std::vector<double> varMean;
        for (double v : pt.sampleVariance) varMean.push_back(v / 256.0);
        PixelZ z = pixelZ(pt.mean, varMean, m.mean, m.semSum, 3.5);
        double se = std::sqrt(pt.meanRatioSe * pt.meanRatioSe + m.meanSem() * m.meanSem());
        double ratio = meanValue(pt.mean) / meanValue(m.mean), zMean = (meanValue(pt.mean) - meanValue(m.mean)) / se;
        std::printf("[figure] %s: path tracer 256 spp / Mitsuba: mean ratio %.5f (z %.2f); |z| < 3.5 on %.2f%% of "
                    "the pixels (max %.2f)\n",
                    name.c_str(), ratio, zMean, 100 * z.passFraction(), z.maxAbsZ);
        EXPECT_GE(z.passFraction(), 0.99) << name;
        EXPECT_LT(z.maxAbsZ, 10.0) << name;
        EXPECT_LT(std::abs(zMean), 4.0) << name;
        EXPECT_NEAR(ratio, 1.0, 0.01) << name;
    }
}

namespace {

// cornell-spheres-point's stored reference holds the light its point lamp sends through the mirror
// and glass balls, found by the light tracer (reference/light_tracer.h); Mitsuba's path tracer
// lacks it as photoncl's path tracer alone does. So the reference less the light tracer's own
// share (256 passes of 64 × 64 light paths, rendered here) must match Mitsuba's mean within
// 0.5 % (measured 0.99985 with uniform emission, 1.00029 aimed), and the reference itself must be brighter than Mitsuba by about that
// share (measured +3.76 %; the share is 3.6 % of the reference).
void expectLightTracedShareExplainsTheDifference(const std::string& name, const Image& ref, const MitsubaReference& m) {
    Scene scene = loadSceneAt(name, ref.width, ref.height);
    ASSERT_NE(pathsThePathTracerMisses(scene), "") << name;
    SceneGeometry geometry = SceneGeometry::build(scene);
    LightTracerSettings s;
    s.seed = 5;
    s.passes = 256;
    s.threads = 2;
    Film film(ref.width, ref.height);
    LightTracer(scene, geometry, s).render(film);
    double share = 0.0;
    for (double v : film.sums()) share += v / s.passes;
    share /= double(film.sums().size());
    const double mitsuba = meanValue(m.mean), stored = meanValue(ref);
    std::printf("[figure] %s: stored reference / Mitsuba: mean ratio %.5f; light-traced share %.5f (%.2f%% of the "
                "reference); (reference - share) / Mitsuba %.5f\n",
                name.c_str(), stored / mitsuba, share, 100.0 * share / stored, (stored - share) / mitsuba);
    EXPECT_NEAR((stored - share) / mitsuba, 1.0, 0.005) << name;
    EXPECT_GT(stored / mitsuba, 1.03) << name;
}

}  // namespace

// The stored path-traced references (tests/data/ref-*.exr, 4096-32768 samples) against Mitsuba,
// per pixel: the reference's variance is the path tracer's per-sample variance (pathTraced) over
// its sample count. Bounds: |z| < 3.5 on at least 99 % of the pixels (cornell-spheres: 98 %;
// both sides' variances come from samples that under-represent its rare caustic paths, and nearly all
// of its 53 failing pixels are brighter in the file with twice the samples: scattered over the
// walls, not at any edge); image means within 0.5 % (both standard errors ≤ 0.1 %).
// cornell-spheres-point's reference adds the light tracer's share: held in the mean, above.
// cornell-fog: 95 %. The same glass ball lights the fog everywhere by rare paths, and Mitsuba's
// 4096 samples per pixel under-represent them more: all of its 160 failing pixels (3.9 %) are
// brighter in the stored reference, none darker, scattered over the image, while the image means
// agree to 3e-5 and the fresh 256-sample render agrees per pixel on 100 % (above).
TEST(MitsubaReferences, StoredReferencesAgree) {
    ASSERT_TRUE(haveOpenImageIO()) << "the references are EXR";
    for (const std::string& name : mitsubaScenes()) {
        MitsubaReference m = readMitsuba(name);
        ImageMetadata meta;
        Image ref = readImage(referencePath(name), &meta);
        const double refSpp = static_cast<double>(meta.samples);  // as make_references.py recorded it
        ASSERT_GE(refSpp, 4096) << name;
        if (name == "cornell-spheres-point.json") {
            expectLightTracedShareExplainsTheDifference(name, ref, m);
            continue;
        }
        std::vector<double> varRef;
        for (double v : pathTraced(name, m).sampleVariance) varRef.push_back(v / refSpp);
        PixelZ z = pixelZ(ref, varRef, m.mean, m.semSum, 3.5);
        ImageErrors e = compare(ref, m.mean);
        std::printf("[figure] %s: stored reference (%.0f spp) / Mitsuba: %s; |z| < 3.5 on %.2f%% (max %.2f)\n",
                    name.c_str(), refSpp, formatErrors(e).c_str(), 100 * z.passFraction(), z.maxAbsZ);
        const double required = name == "cornell-spheres.json" ? 0.98 : name == "media/cornell-fog.json" ? 0.95 : 0.99;
        EXPECT_GE(z.passFraction(), required) << name;
        EXPECT_NEAR(e.meanRatio, 1.0, 0.005) << name;
    }
}

// Every photon method against Mitsuba. The methods are biased (the density estimate blurs light
// into dark corners and out of bright edges), so they are held on the image mean, on relMSE and
// on 8×8 block means of R+G+B, not per pixel. Settings as in photon_render_test.cpp: fg 2 passes
// × 4 spp, 32 gather rays, 8 light samples, 50k + 50k photons per pass (bounds there, against
// ref-*.exr: mean 2 %, relMSE 0.03); direct 2 passes × 4 spp, 100k + 100k; progressive 8 passes
// × 4 spp of 50k + 50k. Bounds, Cornell scenes: mean within 1 % for fg (measured within 0.1 %),
// 1.5 % for direct and progressive (measured −0.2 % and −0.7 %), relMSE < 0.03, every
// 8×8 block within 16 % and at least 80 % of the blocks within 5 % (the worst blocks are the box's
// corners, where every method's boundary bias darkens the estimate; against ref-*.exr the same
// blocks are off by the same amounts). Furnaces (L = 1, 4 everywhere, no corners): mean within
// 1 % (photon_render_test.cpp's bound against the closed form; measured up to +0.8 %, direct),
// every 8×8 block within 5 % (measured up to 3.7 %).
// Not here: cornell-spheres-point, whose light reflected or refracted from a point light
// (LS+D…) no path tracer finds (Mitsuba's neither), so photon mapping is brighter by design
// (+4.5 %); photon_render_test.cpp holds it to the light-traced reference instead.
TEST(MitsubaReferences, PhotonMethodsAgree) {
    ASSERT_TRUE(haveOpenImageIO()) << "the references are EXR";
    for (const std::string name :
         {"cornell-box.json", "cornell-spheres.json", "furnace-0.5.json", "furnace-0.8.json"}) {
        const bool furnace = name.rfind("furnace", 0) == 0;
        MitsubaReference m = readMitsuba(name);
        auto p = test::prepareFile(name, m.mean.width, m.mean.height);
        for (RenderMethod method :
             {RenderMethod::FinalGather, RenderMethod::DirectVisualisation, RenderMethod::Progressive}) {
            PhotonRenderSettings s;
            s.method = method;
            s.passes = method == RenderMethod::Progressive ? 8 : 2;
            s.strata = 2;
            s.gatherRays = 32;
            s.lightSamples = 8;
            s.globalPhotons = method == RenderMethod::DirectVisualisation ? 100000 : 50000;
            s.causticPhotons = s.globalPhotons;
            s.seed = 3;
            const PhotonRenderResult r = test::render(*p, s);
            const Image img = r.film.resolve();
            ImageErrors e = compare(img, m.mean);
            BlockErrors b = blockErrors(img, m.mean, 8, 0.05);
            const std::string what = name + " " + renderMethodName(method);
            std::printf("[figure] %s / Mitsuba (%.1f s): %s; 8x8 blocks: worst %.2f%% (block %d), %.0f%% within 5%%\n",
                        what.c_str(), r.times.total, formatErrors(e).c_str(), 100 * b.worst, b.worstIndex,
                        100 * b.fractionWithin);
            test::expectFinite(r, img, what);
            if (furnace) {
                EXPECT_NEAR(e.meanRatio, 1.0, 0.01) << what;
                EXPECT_LT(b.worst, 0.05) << what;
            } else {
                EXPECT_NEAR(e.meanRatio, 1.0, method == RenderMethod::FinalGather ? 0.01 : 0.015) << what;
                EXPECT_LT(e.relMse, 0.03) << what;
                EXPECT_LT(b.worst, 0.16) << what;
                EXPECT_GE(b.fractionWithin, 0.8) << what;
            }
        }
    }
}
