// The textured, sky-lit asset (issue 18, scenes/courtyard/, written by
// scripts/make_courtyard_scene.py): a glTF with base-colour textures, included by a JSON scene
// under an image sky whose sun is one texel. fg and progressive at the reference's width (64)
// against the path-traced reference (tests/data/ref-courtyard.exr): every part of the pipeline
// that the asset exercises at once (texture lookups at photon, eye and gather hits, the sky's
// photons with the caustic pass aimed at the glass ball, escapes and direct light by the sky's
// map) has to add up to the same image.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "accuracy/accuracy_common.h"
#include "common/optional_feature.h"
#include "common/prepared_render.h"

using namespace pcl;
using namespace pcl::accuracy;
using test::expectFinite;
using test::prepareFile;

// 8 passes × 2×2 eye samples, 100k + 100k photons a pass: mean within 2 % of the reference and
// relMSE under 0.05 (measured: fg 0.9958 and 0.0046, progressive 0.9953 and 0.0063; the
// reference's own relMSE is 0.0011).
TEST(CourtyardAccuracy, PhotonMethodsMatchTheReference) {
    PCL_REQUIRE_FEATURE(haveOpenImageIO(), "OpenImageIO (the reference is EXR, the textures PNG)");
    const std::string name = texturedScenes().front();
    const Image ref = readImage(referencePath(name));
    auto p = prepareFile(name, ref.width, ref.height);
    ASSERT_TRUE(p->plan.causticMap) << "the glass ball under the sky: a caustic map";
    for (RenderMethod method : {RenderMethod::FinalGather, RenderMethod::Progressive}) {
        PhotonRenderSettings s;
        s.method = method;
        s.passes = 8;
        s.strata = 2;
        s.gatherRays = 8;
        s.lightSamples = 4;
        s.causticK = 20;
        s.globalPhotons = 100000;
        s.causticPhotons = 100000;
        s.seed = 3;
        const PhotonRenderResult r = test::render(*p, s);
        const Image img = r.film.resolve();
        const ImageErrors e = compare(img, ref);
        std::printf("[figure] courtyard %s (64 wide, 8 passes x 4 spp, 100k+100k photons, %.1f s): %s\n",
                    renderMethodName(method), r.times.total, formatErrors(e).c_str());
        EXPECT_NEAR(e.meanRatio, 1.0, 0.02) << renderMethodName(method);
        EXPECT_LT(e.relMse, 0.05) << renderMethodName(method);
        expectFinite(r, img, renderMethodName(method));
    }
}
