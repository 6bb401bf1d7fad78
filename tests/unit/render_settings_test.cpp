// Render settings (render/render_settings.h): the defaults per method and plan with their
// reasons, what a request overrides, the words users type, validation, and the one
// serialisation of what changes a pixel: every such setting changes the text, no run control
// does, and the text is the one batch shards have always recorded.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "core/clock.h"
#include "core/error.h"
#include "prep/prepared_scene.h"
#include "render/render_settings.h"
#include "scene/load_scene.h"

using namespace pcl;

namespace {

RenderPlan planOf(const std::string& name) {
    Scene s = loadScene(std::string(PHOTONCL_SOURCE_DIR) + "/scenes/" + name);
    return prepareScene(s).plan;
}

ResolvedSettings resolve(const std::string& method, const RenderPlan& plan,
                         const std::function<void(RenderRequest&)>& given = {}) {
    RenderRequest q;
    q.method = method;
    if (given) given(q);
    return resolveRenderSettings(q, plan, 256, 256);
}

const SettingChoice* choice(const ResolvedSettings& r, const std::string& prefix) {
    for (const SettingChoice& c : r.choices)
        if (c.what.rfind(prefix, 0) == 0) return &c;
    return nullptr;
}

}  // namespace

TEST(RenderSettings, DefaultsPerMethodFollowThePlan) {
    const RenderPlan box = planOf("cornell-box.json"), dof = planOf("motion-dof.json"),
                     spheres = planOf("cornell-spheres.json");
    ASSERT_FALSE(box.lensSampling || box.timeSampling || box.glossySampling || box.causticMap);
    ASSERT_TRUE(dof.lensSampling || dof.timeSampling);
    ASSERT_TRUE(spheres.causticMap);
    // No k-nearest search per eye sample: 6x6 eye samples of 2 gather rays and 2 shadow rays.
    const PhotonRenderSettings fg = resolve("fg", box).settings;
    EXPECT_EQ(fg.method, RenderMethod::FinalGather);
    EXPECT_EQ(fg.strata, 6u);
    EXPECT_EQ(fg.gatherRays, 2u);
    EXPECT_EQ(fg.lightSamples, 2u);
    EXPECT_TRUE(fgEyeSamplesAreCheap(fg, box));
    // Caustics by connections (the default where nothing moves): eye samples stay cheap, 6x6, and
    // the caustic map is read through mirrors and glass with 20 photons an estimate.
    const PhotonRenderSettings fgConnect = resolve("fg", spheres).settings;
    EXPECT_TRUE(fgConnect.causticConnections);
    EXPECT_TRUE(fgEyeSamplesAreCheap(fgConnect, spheres));
    EXPECT_FALSE(fgEyeSamplesReadCaustics(fgConnect, spheres));
    EXPECT_EQ(fgConnect.strata, 6u);
    EXPECT_EQ(fgConnect.gatherRays, 2u);
    EXPECT_EQ(fgConnect.causticK, 20u);
    EXPECT_FALSE(fg.causticConnections);  // no caustic map, nothing to connect
    // The scene moves: connections too (each at its photon's shutter time), and the map on request.
    EXPECT_TRUE(resolve("fg", dof).settings.causticConnections);
    EXPECT_FALSE(resolve("fg", dof, [](RenderRequest& q) { q.caustics = "map"; }).settings.causticConnections);
    EXPECT_THROW(resolve("fg", spheres, [](RenderRequest& q) { q.caustics = "both"; }), InputError);
    // The caustic map at every eye hit (a k-nearest estimate per eye hit): 4x4 eye samples of 4
    // gather rays, 2 shadow rays, 20 photons per caustic estimate.
    const PhotonRenderSettings fgCaustic =
        resolve("fg", spheres, [](RenderRequest& q) { q.caustics = "map"; }).settings;
    EXPECT_FALSE(fgEyeSamplesAreCheap(fgCaustic, spheres));
    EXPECT_TRUE(fgEyeSamplesReadCaustics(fgCaustic, spheres));
    EXPECT_EQ(fgCaustic.strata, 4u);
    EXPECT_EQ(fgCaustic.gatherRays, 4u);
    EXPECT_EQ(fgCaustic.lightSamples, 2u);
    EXPECT_EQ(fgCaustic.causticK, 20u);
    EXPECT_EQ(fgCaustic.globalK, 50u);
    // Gather importance (a k-nearest search per eye hit for its histogram): few eye samples.
    const PhotonRenderSettings fgImportance =
        resolve("fg", box, [](RenderRequest& q) { q.gatherImportance = 4; }).settings;
    EXPECT_EQ(fgImportance.strata, 1u);
    EXPECT_EQ(fgImportance.gatherRays, 64u);
    EXPECT_EQ(fgImportance.lightSamples, 16u);
    EXPECT_EQ(fgImportance.causticK, 50u);
    EXPECT_EQ(fg.globalK, 50u);
    EXPECT_EQ(fg.causticK, 50u);
    EXPECT_EQ(fg.globalPhotons, box.globalPhotons);
    // fg's emitter samples: up to 16x16 where a probe sees an emitter's edge; the other methods
    // have none; a given 0 turns them off. The text records them only when on (so renders and
    // shards without them keep their settings hash).
    EXPECT_EQ(fg.emitterStrata, 16u);
    EXPECT_EQ(resolve("fg", box, [](RenderRequest& q) { q.emitterStrata = 0; }).settings.emitterStrata, 0u);
    EXPECT_EQ(resolve("fg", box, [](RenderRequest& q) { q.emitterStrata = 5; }).settings.emitterStrata, 5u);
    EXPECT_NE(settingsText(fg, box, 64, 64, 1).find(";emitterStrata=16"), std::string::npos);
    EXPECT_EQ(settingsText(resolve("fg", box, [](RenderRequest& q) { q.emitterStrata = 0; }).settings, box, 64, 64, 1)
                  .find("emitterStrata"),
              std::string::npos);
    EXPECT_EQ(resolve("direct", box).settings.emitterStrata, 0u);
    EXPECT_EQ(resolve("progressive", box).settings.emitterStrata, 0u);
    EXPECT_EQ(fg.passes, defaultPasses(RenderMethod::FinalGather, 256, 256));
    EXPECT_EQ(fg.passes, 10u);
    // A lens and a shutter: the eye samples sample them too (motion-dof's caustics are connected:
    // its eye samples stay cheap, 6x6 of 2).
    const PhotonRenderSettings fgDof = resolve("fg", dof).settings;
    ASSERT_TRUE(dof.causticMap);
    EXPECT_EQ(fgDof.strata, 6u);
    EXPECT_EQ(fgDof.gatherRays, 2u);
    const PhotonRenderSettings direct = resolve("direct", box).settings;
    EXPECT_EQ(direct.strata, 2u);
    EXPECT_EQ(direct.passes, 4u);
    const PhotonRenderSettings progressive = resolve("progressive", box).settings;
    EXPECT_EQ(progressive.strata, 2u);  // on surfaces; in media one (each eye sample pays a beam estimate)
    EXPECT_EQ(progressive.passes, 32u);
    RenderPlan fog = box;
    fog.volumeMap = true;
    EXPECT_EQ(resolve("progressive", fog).settings.strata, 1u);
    // The struct's own defaults are the render's where the render does not choose per scene (k),
    // and the few-eye-samples choice otherwise (what the engine's callers and tests build on).
    const PhotonRenderSettings plain;
    EXPECT_EQ(plain.lightSamples, fgImportance.lightSamples);
    EXPECT_EQ(plain.globalK, fg.globalK);
    EXPECT_EQ(plain.causticK, fgImportance.causticK);
    EXPECT_EQ(plain.gatherRays, fgImportance.gatherRays);
    EXPECT_EQ(plain.strata, fgImportance.strata);
}

TEST(RenderSettings, EveryDefaultSaysWhyAndEveryGivenValueSaysGiven) {
    const RenderPlan box = planOf("cornell-box.json");
    const ResolvedSettings d = resolve("fg", box);
    ASSERT_GE(d.choices.size(), 6u);
    for (const SettingChoice& c : d.choices) {
        EXPECT_FALSE(c.given) << c.what;
        EXPECT_FALSE(c.reason.empty()) << c.what;
    }
    const ResolvedSettings g = resolve("fg", box, [](RenderRequest& q) {
        q.gatherRays = 8;
        q.k = 20;
        q.passes = 3;
    });
    EXPECT_EQ(g.settings.gatherRays, 8u);
    EXPECT_EQ(g.settings.globalK, 20u);
    EXPECT_EQ(g.settings.passes, 3u);
    ASSERT_NE(choice(g, "gather rays"), nullptr);
    EXPECT_TRUE(choice(g, "gather rays")->given);
    EXPECT_TRUE(choice(g, "passes")->given);
    EXPECT_FALSE(choice(g, "light samples")->given);
    EXPECT_NE(g.log().find("gather rays 8  (given)"), std::string::npos) << g.log();
    EXPECT_NE(g.log().find("light samples 2  (default: "), std::string::npos) << g.log();
    // A time budget leaves the pass count open.
    const PhotonRenderSettings timed = resolve("fg", box, [](RenderRequest& q) { q.seconds = 5; }).settings;
    EXPECT_EQ(timed.passes, 0u);
    EXPECT_EQ(timed.seconds, 5.0);
}

TEST(RenderSettings, TimeBudgetEndsWithinHalfAPass) {
    // The first pass always runs, even past the budget.
    EXPECT_TRUE(anotherPassFits(50.0, 10.0, 0, 0.0));
    // Passes of 4 s (2 done in 8 s): a third would end at 12 s, 2 s past 10 = stopping 2 s short:
    // it runs (ties go on); with passes of 4.2 s it would end 2.6 s past and stops at 8.4 s.
    EXPECT_TRUE(anotherPassFits(8.0, 10.0, 2, 8.0));
    EXPECT_FALSE(anotherPassFits(8.4, 10.0, 2, 8.4));
    // Short passes run until the budget is (nearly) spent.
    EXPECT_TRUE(anotherPassFits(9.9, 10.0, 99, 9.9));
    EXPECT_FALSE(anotherPassFits(10.0, 10.0, 100, 10.0));
}

TEST(RenderSettings, OverridesOnlyWhereTheMethodHasTheSetting) {
    const RenderPlan box = planOf("cornell-box.json");
    auto given = [](RenderRequest& q) {
        q.gatherRays = 7;
        q.strata = 3;
    };
    EXPECT_EQ(resolve("direct", box, given).settings.gatherRays, 1u);  // only fg gathers
    EXPECT_EQ(resolve("direct", box, given).settings.strata, 3u);
    EXPECT_EQ(resolve("fg", box, given).settings.gatherRays, 7u);
    EXPECT_EQ(resolve("path", box, given).settings.strata, 1u);  // the path tracer has no strata
}

TEST(RenderSettings, NamesRoundTripAndUnknownNamesAreRefusedByName) {
    for (RenderMethod m : {RenderMethod::FinalGather, RenderMethod::DirectVisualisation, RenderMethod::Progressive,
                           RenderMethod::PathTracing})
        EXPECT_EQ(parseRenderMethod(renderMethodName(m)), m);
    for (GatherSource g : {GatherSource::Precomputed, GatherSource::Estimate})
        EXPECT_EQ(parseGatherSource(gatherSourceName(g)), g);
    for (KnnStructure s : {KnnStructure::KdTree, KnnStructure::HashGrid})
        EXPECT_EQ(parseKnnStructure(knnStructureWord(s)), s);
    auto message = [](const std::function<void()>& f) {
        try {
            f();
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("(no error)");
    };
    EXPECT_NE(message([] { parseRenderMethod("pm"); }).find("expected fg, direct, progressive or path"),
              std::string::npos);
    EXPECT_NE(message([] { parseGatherSource("lookup"); }).find("expected precomputed or estimate"), std::string::npos);
    EXPECT_NE(message([] { parseKnnStructure("octree"); }).find("expected kd-tree or hash-grid"), std::string::npos);
    const RenderPlan box = planOf("cornell-box.json");
    EXPECT_THROW(resolve("fg", box, [](RenderRequest& q) { q.filter = "triangle"; }), InputError);
}

TEST(RenderSettings, ValidationRefusesOutOfRangeSettings) {
    PhotonRenderSettings s;
    EXPECT_NO_THROW(validateRenderSettings(s));
    auto bad = [](const std::function<void(PhotonRenderSettings&)>& f) {
        PhotonRenderSettings s;
        f(s);
        EXPECT_THROW(validateRenderSettings(s), InputError);
    };
    bad([](PhotonRenderSettings& s) { s.strata = 0; });
    bad([](PhotonRenderSettings& s) { s.strata = 17; });
    bad([](PhotonRenderSettings& s) { s.emitterStrata = 17; });
    bad([](PhotonRenderSettings& s) { s.gatherRays = 0; });
    bad([](PhotonRenderSettings& s) { s.globalK = PCL_KNN_MAX_K + 1; });
    bad([](PhotonRenderSettings& s) { s.causticK = 0; });
    bad([](PhotonRenderSettings& s) { s.alpha = 1.0f; });
    bad([](PhotonRenderSettings& s) { s.passes = 0; });
    // The user's boundary for what the stages below take as a contract (InternalError there).
    bad([](PhotonRenderSettings& s) { s.histogramCells = PCL_GATHER_MAX_CELLS + 1; });
    bad([](PhotonRenderSettings& s) { s.maxRadius = -1.0f; });
    bad([](PhotonRenderSettings& s) { s.maxRadius = INFINITY; });
    bad([](PhotonRenderSettings& s) { s.initialRadius = NAN; });
}

// The text batch shards recorded before the settings had one home (batch_render.cpp's own
// serialisation): shards written then still merge with shards written now.
TEST(RenderSettings, TextIsTheBatchShardFormat) {
    const RenderPlan spheres = planOf("cornell-spheres.json");
    // The values render chose by default when the format was fixed (given here, as a job would).
    const PhotonRenderSettings fg = resolve("fg", spheres, [](RenderRequest& q) {
                                        q.strata = 1;
                                        q.gatherRays = 64;
                                        q.lightSamples = 16;
                                        q.causticK = 50;
                                        q.caustics = "map";    // the only kind then
                                        q.emitterStrata = 0;   // none then
                                        q.closeGather = 0.0f;  // none then
                                    }).settings;
    EXPECT_EQ(settingsText(fg, spheres, 64, 48, 7),
              "method=fg;width=64;height=48;passes=7;seed=0;strata=1;globalPhotons=200000;causticPhotons=100000;"
              "k=50;causticK=50;gatherRays=64;lightSamples=16;eyeDepth=8;maxRadius=0x0p+0;filter=cone;visibility=0;"
              "gatherSource=precomputed;structure=kd-tree;gatherImportance=0;alpha=0x1.555556p-1;"
              "progressiveK0=0x1.4p+4;radius=0x0p+0;fixedPointBits=32");
    const PhotonRenderSettings path = resolve("path", spheres).settings;
    EXPECT_EQ(settingsText(path, spheres, 64, 48, 9),
              "method=path;width=64;height=48;passes=9;seed=0;samplesPerPass=1;fixedPointBits=32");
    EXPECT_EQ(settingsHash("abc"), 0xe71fa2190541574bull);  // FNV-1a 64 of "abc"
}

TEST(RenderSettings, EverySettingThatChangesAPixelChangesTheTextAndNoRunControlDoes) {
    const RenderPlan spheres = planOf("cornell-spheres.json");
    const PhotonRenderSettings base = resolve("progressive", spheres).settings;
    const std::string text = settingsText(base, spheres, 64, 48, 7);
    const std::vector<std::pair<const char*, std::function<void(PhotonRenderSettings&)>>> pixel = {
        {"method", [](PhotonRenderSettings& s) { s.method = RenderMethod::FinalGather; }},
        {"strata", [](PhotonRenderSettings& s) { s.strata += 1; }},
        {"globalPhotons", [](PhotonRenderSettings& s) { s.globalPhotons += 1; }},
        {"causticPhotons", [](PhotonRenderSettings& s) { s.causticPhotons += 1; }},
        {"globalK", [](PhotonRenderSettings& s) { s.globalK += 1; }},
        {"causticK", [](PhotonRenderSettings& s) { s.causticK += 1; }},
        {"gatherRays", [](PhotonRenderSettings& s) { s.gatherRays += 1; }},
        {"lightSamples", [](PhotonRenderSettings& s) { s.lightSamples += 1; }},
        {"eyeDepth", [](PhotonRenderSettings& s) { s.eyeDepth = 3; }},
        {"maxRadius", [](PhotonRenderSettings& s) { s.maxRadius = 0.25f; }},
        {"filter", [](PhotonRenderSettings& s) { s.filter = EstimateFilter::Gaussian; }},
        {"structure", [](PhotonRenderSettings& s) { s.structure = KnnStructure::HashGrid; }},
        {"visibility", [](PhotonRenderSettings& s) { s.visibility = true; }},
        {"gatherSource", [](PhotonRenderSettings& s) { s.gatherSource = GatherSource::Estimate; }},
        {"histogramCells", [](PhotonRenderSettings& s) { s.histogramCells = 4; }},
        {"alpha", [](PhotonRenderSettings& s) { s.alpha = std::nextafter(s.alpha, 1.0f); }},
        {"progressiveK0", [](PhotonRenderSettings& s) { s.progressiveK0 = 21.0f; }},
        {"initialRadius", [](PhotonRenderSettings& s) { s.initialRadius = 0.1f; }},
        {"seed", [](PhotonRenderSettings& s) { s.seed = 5; }},
    };
    for (const auto& [name, change] : pixel) {
        PhotonRenderSettings s = base;
        change(s);
        EXPECT_NE(settingsText(s, spheres, 64, 48, 7), text) << name << " is missing from settingsFields";
    }
    EXPECT_NE(settingsText(base, spheres, 65, 48, 7), text);
    EXPECT_NE(settingsText(base, spheres, 64, 48, 8), text);
    const std::vector<std::pair<const char*, std::function<void(PhotonRenderSettings&)>>> controls = {
        {"passes", [](PhotonRenderSettings& s) { s.passes = 99; }},  // the text takes the passes rendered
        {"firstPass", [](PhotonRenderSettings& s) { s.firstPass = 3; }},
        {"seconds", [](PhotonRenderSettings& s) { s.seconds = 10; }},
        {"photonBatch", [](PhotonRenderSettings& s) { s.photonBatch = 4096; }},
        {"aovs", [](PhotonRenderSettings& s) { s.aovs = true; }},
        {"chunkSamples", [](PhotonRenderSettings& s) { s.chunkSamples = 512; }},
        {"log", [](PhotonRenderSettings& s) { s.log = true; }},
    };
    for (const auto& [name, change] : controls) {
        PhotonRenderSettings s = base;
        change(s);
        EXPECT_EQ(settingsText(s, spheres, 64, 48, 7), text) << name << " changes no pixel";
    }
}
