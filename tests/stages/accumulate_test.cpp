// The accumulate stage (kernels/accumulate.cl; render/twin_stages.cpp on the twin's side): each
// eye sample's radiance summed where its parts are and read back as one value. A render without
// AOVs adds those sums to its film; a render with AOVs reads the records and every part and adds
// them on the host (render/photon_renderer.cpp). The two films must hold the same bits, on the
// device and on the twin: the sum's order, the emitter spans (fg's lamp edges, whose emitted
// light the emitter samples give) and the two volume maps' parts (media) included. (A kernel
// from PHOTONCL_KERNEL_DIR that ignores the spans fails the first test; one that adds indirect
// before caustic fails the other two.)
#include <gtest/gtest.h>

#include <string>

#include "accuracy/accuracy_common.h"
#include "device_fixture.h"
#include "prep/prepared_scene.h"
#include "render/photon_renderer.h"

namespace pcl {
namespace {

PhotonRenderSettings settingsFor(RenderMethod method, bool aovs) {
    PhotonRenderSettings s;
    s.method = method;
    s.passes = 2;
    s.strata = 1;
    s.globalPhotons = 5000;
    s.causticPhotons = 5000;
    s.gatherRays = 4;
    s.lightSamples = 1;
    if (method == RenderMethod::FinalGather) s.emitterStrata = 4;
    s.seed = 11;
    s.aovs = aovs;
    return s;
}

void expectSameFilms(const std::string& sceneName, RenderMethod method, bool expectSpans) {
    const Scene scene = accuracy::loadSceneAt(sceneName, 32, 24);
    const PreparedScene p = prepareScene(scene);
    const std::string what = sceneName + " " + renderMethodName(method);
    for (bool twin : {false, true}) {
        auto render = [&](bool aovs) {
            const PhotonRenderSettings s = settingsFor(method, aovs);
            return twin ? renderPhotonMappedTwin(scene, p.geometry, p.buffers, p.plan, s)
                        : renderPhotonMapped(test::testDevice(), scene, p.geometry, p.buffers, p.plan, s);
        };
        const PhotonRenderResult sums = render(false), parts = render(true);
        const std::string side = what + (twin ? " (twin)" : " (device)");
        ASSERT_EQ(sums.film.sums().size(), parts.film.sums().size()) << side;
        size_t differing = 0;
        for (size_t i = 0; i < sums.film.sums().size(); ++i) differing += sums.film.sums()[i] != parts.film.sums()[i];
        EXPECT_EQ(differing, 0u) << side << ": the accumulate stage's sums differ from the parts added on the host";
        EXPECT_EQ(sums.film.weights(), parts.film.weights()) << side;
        EXPECT_EQ(sums.nonFiniteSamples, parts.nonFiniteSamples) << side;
        EXPECT_EQ(sums.nonFiniteSamples, 0u) << side;
        EXPECT_GT(sums.film.totalWeight(), 0.0) << side;
        if (expectSpans) {
            EXPECT_GT(sums.emitterPixels, 0u) << side << ": no emitter spans to leave out";
        }
    }
}

TEST(Accumulate, SumsEqualThePartsAddedOnTheHostWithEmitterSpans) {
    expectSameFilms("cornell-box.json", RenderMethod::FinalGather, true);
}

TEST(Accumulate, SumsEqualThePartsAddedOnTheHostWithCausticAndIndirectParts) {
    expectSameFilms("cornell-spheres.json", RenderMethod::Progressive, false);
    expectSameFilms("cornell-spheres.json", RenderMethod::DirectVisualisation, false);
}

TEST(Accumulate, SumsEqualThePartsAddedOnTheHostWithVolumeParts) {
    expectSameFilms("media/cornell-fog.json", RenderMethod::Progressive, false);
}

}  // namespace
}  // namespace pcl
