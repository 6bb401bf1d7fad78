// The whole photon-mapped render on the device (renderPhotonMapped) against the same render on
// the CPU twin's stages (renderPhotonMappedTwin, no OpenCL), same settings and seeds, per pixel,
// for every shipped scene and the three photon methods. The two share the loop and the film
// (host code, render/photon_renderer.cpp); every stage in between is the kernel on one side and
// its twin on the other, so this chains the stage checks end to end.
//
// Each device render is compared twice:
//  * with the twin given the device's photons (render/shared_photons.h): the eye pass, held per
//    pixel. A value matches at 1e-3 relative (+ 1e-6 of the image's peak), the stage checks'
//    tolerance (float rounding in other orders); ≥ 99 % of the pixels must match, since a rare
//    eye or gather path that rounding sends the other way at an edge moves its pixel by a lot
//    (measured: ≤ 1 pixel in 768 per scene and method); the image means within 5e-4 relative
//    (one such pixel of 768 off by 25 % moves the mean by 3e-4; measured ≤ 5.4e-5) and no pixel
//    off by more than 25 % of the peak (measured ≤ 7.6 %).
//  * with the twin's own photon pass: `check --stage pass` lets ≤ 0.1 % of paths diverge
//    (measured 0.05 % on gltf-room), and with precomputed irradiance one divergent path shifts
//    which photons are selected after it, so the fg pixels differ by the precomputation's noise
//    (gltf-room: 0.5 % of pixels within 1e-3). Held: image means within 5e-3 relative (measured
//    ≤ 1.7e-3) and no pixel off by more than 25 % of the peak (measured ≤ 7.9 %).
// A 1 % error in one kernel fails the first on every scene (kernels from PHOTONCL_KERNEL_DIR with
// the radiance of final_gather.cl's resolve, eye_estimate.cl's resolve or direct_light.cl × 1.01:
// 0–56 % of the pixels of the methods reading it match). Each sample's sum of its parts is a
// stage too (accumulate: the kernel here, the twin's own sum there; accumulate_test.cpp holds it
// to the bits of the parts added on the host); adding the sums to the film is host code both
// renders share (render/photon_renderer.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "accuracy/accuracy_common.h"
#include "check/render.h"
#include "common/test_scenes.h"
#include "core/clock.h"
#include "device_fixture.h"
#include "prep/prepared_scene.h"
#include "render/device_stages.h"
#include "render/photon_renderer.h"
#include "render/shared_photons.h"
#include "render/twin_stages.h"

namespace pcl {
namespace {

constexpr double kValueTolerance = 1e-3;    // per value, relative (the stage checks')
constexpr double kPixelsMatching = 0.99;    // fraction of pixels within it
constexpr double kMeanTolerance = 5e-4;     // relative difference of the image means
constexpr double kWorstOfPeak = 0.25;       // largest |d − t| over the image's peak
constexpr double kOwnMeanTolerance = 5e-3;  // own photon passes: image means
constexpr double kOwnWorstOfPeak = 0.25;    // own photon passes: largest |d − t| over the peak

struct FilmComparison {
    StageComparison pixels;
    double meanRel = 0.0;      // |mean(d) − mean(t)| / mean(t)
    double worstOfPeak = 0.0;  // max |d − t| / peak(t)
};

FilmComparison compareFilms(const Image& dev, const Image& twin) {
    FilmComparison c;
    c.pixels = compareValues("film", dev.rgb, twin.rgb, 3, kValueTolerance, 3);
    double sd = 0.0, st = 0.0, peak = 0.0, worst = 0.0;
    for (size_t i = 0; i < twin.rgb.size(); ++i) {
        sd += dev.rgb[i];
        st += twin.rgb[i];
        peak = std::max(peak, double(std::fabs(twin.rgb[i])));
        worst = std::max(worst, double(std::fabs(dev.rgb[i] - twin.rgb[i])));
    }
    c.meanRel = st > 0.0 ? std::fabs(sd - st) / st : std::fabs(sd);
    c.worstOfPeak = peak > 0.0 ? worst / peak : worst;
    return c;
}

// The device render, the twin render given the device's photons, and the twin's own render.
struct Renders {
    Image device, twinSharedPhotons, twin;
    double deviceSeconds = 0.0, twinSeconds = 0.0;
};

Renders renderThree(const Scene& scene, const PreparedScene& p, const PhotonRenderSettings& s) {
    Renders r;
    PhotonPassRecord photons;
    auto t = Clock::now();
    {
        DeviceRenderStages dev(test::testDevice(), scene, p.geometry, p.buffers, s);
        SharedPhotonStages recording(dev, photons, SharedPhotonStages::Mode::Record);
        r.device = renderPhotonMapped(recording, scene, p.geometry, p.buffers, p.plan, s).film.resolve();
    }
    r.deviceSeconds = since(t);
    TwinRenderStages twin(scene, p.geometry, p.buffers);
    SharedPhotonStages replaying(twin, photons, SharedPhotonStages::Mode::Replay);
    r.twinSharedPhotons = renderPhotonMapped(replaying, scene, p.geometry, p.buffers, p.plan, s).film.resolve();
    t = Clock::now();
    r.twin = renderPhotonMappedTwin(scene, p.geometry, p.buffers, p.plan, s).film.resolve();
    r.twinSeconds = since(t);
    return r;
}

void printFigure(const std::string& what, const FilmComparison& c) {
    const StageComparison& px = c.pixels;
    std::printf("[figure] render twin %s: %.2f %% of %zu pixels within %.0e, max rel %.3e, mean rel %.3e, worst %.3e "
                "of peak\n",
                what.c_str(), 100.0 * px.fraction(), px.compared, kValueTolerance, px.maxRelError, c.meanRel,
                c.worstOfPeak);
    for (const WorstSample& w : px.worst)
        std::printf("  worst pixel %zu: rel %.3e device (%g %g %g) twin (%g %g %g)\n", w.index, w.relError, w.device[0],
                    w.device[1], w.device[2], w.twin[0], w.twin[1], w.twin[2]);
}

// 32×24, one sample per pixel, 5000 + 5000 photons, 8 gather rays, 2 light samples: every
// stage runs (the caustic map where the plan has one; fg's emitter samples where a lamp's edge
// is seen, up to 4 × 4), in about a second per scene and method on either side.
PhotonRenderSettings smallSettings(RenderMethod method) {
    PhotonRenderSettings s;
    s.method = method;
    s.passes = method == RenderMethod::Progressive ? 2 : 1;  // progressive: the radius schedule moves
    s.strata = 1;
    s.globalPhotons = 5000;
    s.causticPhotons = 5000;
    s.gatherRays = 8;
    s.lightSamples = 2;
    if (method == RenderMethod::FinalGather) s.emitterStrata = 4;
    s.seed = 7;
    return s;
}

class RenderTwin : public ::testing::TestWithParam<std::string> {};

TEST_P(RenderTwin, DeviceFilmMatchesTwinFilm) {
    const std::string name = GetParam();
    const Scene scene = accuracy::loadSceneAt(name, 32, 24);
    const PreparedScene prepared = prepareScene(scene);
    for (RenderMethod m : {RenderMethod::FinalGather, RenderMethod::DirectVisualisation, RenderMethod::Progressive}) {
        const Renders r = renderThree(scene, prepared, smallSettings(m));
        const std::string what = name + " " + renderMethodName(m);
        std::printf("[figure] render twin %s: device %.2f s, twin %.2f s\n", what.c_str(), r.deviceSeconds,
                    r.twinSeconds);
        const FilmComparison shared = compareFilms(r.device, r.twinSharedPhotons);
        printFigure(what + " (same photons)", shared);
        const FilmComparison own = compareFilms(r.device, r.twin);
        printFigure(what + " (own photons)", own);

        const StageComparison& px = shared.pixels;
        EXPECT_EQ(px.nonFinite, 0u) << what;
        EXPECT_EQ(px.compared, size_t(32 * 24)) << what;
        EXPECT_GT(px.nonzero, px.compared / 2) << what << ": the image is mostly black";
        EXPECT_GE(px.fraction(), kPixelsMatching) << what;
        EXPECT_LE(shared.meanRel, kMeanTolerance) << what;
        EXPECT_LE(shared.worstOfPeak, kWorstOfPeak) << what;

        EXPECT_EQ(own.pixels.nonFinite, 0u) << what;
        EXPECT_LE(own.meanRel, kOwnMeanTolerance) << what << " (own photons)";
        EXPECT_LE(own.worstOfPeak, kOwnWorstOfPeak) << what << " (own photons)";
    }
}

// A replayed render needs every pass it traces recorded: nothing else stands in for them.
TEST(SharedPhotons, ReplayRefusesAPassNotRecorded) {
    const Scene scene = accuracy::loadSceneAt("cornell-box.json", 8, 6);
    const PreparedScene p = prepareScene(scene);
    PhotonPassRecord record;
    TwinRenderStages twin(scene, p.geometry, p.buffers);
    SharedPhotonStages replaying(twin, record, SharedPhotonStages::Mode::Replay);
    PhotonRenderSettings s = smallSettings(RenderMethod::DirectVisualisation);
    EXPECT_THROW(renderPhotonMapped(replaying, scene, p.geometry, p.buffers, p.plan, s), std::logic_error);
    // Recorded with other photon counts: refused too.
    SharedPhotonStages recording(twin, record, SharedPhotonStages::Mode::Record);
    renderPhotonMapped(recording, scene, p.geometry, p.buffers, p.plan, s);
    EXPECT_NO_THROW(renderPhotonMapped(replaying, scene, p.geometry, p.buffers, p.plan, s));
    s.globalPhotons += 1;
    EXPECT_THROW(renderPhotonMapped(replaying, scene, p.geometry, p.buffers, p.plan, s), std::logic_error);
}

std::vector<std::string> sceneNames() {
    std::vector<std::string> names;
    for (const auto& f : test_scenes::shippedSceneFiles()) names.push_back(f.filename().string());
    return names;
}

INSTANTIATE_TEST_SUITE_P(EveryShippedScene, RenderTwin, ::testing::ValuesIn(sceneNames()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             std::string n = info.param;
                             for (char& ch : n)
                                 if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                             return n;
                         });

}  // namespace
}  // namespace pcl
