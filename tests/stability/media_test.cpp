// Participating media where volume methods fail: thin fog (few volume photons, most light
// passes), dense fog (σt ℓ ≈ 8 across the room: nearly all light scattered many times, direct
// light gone), and strongly forward (g = 0.9) and backward (g = −0.9) phase functions (the beam
// estimate's phase weight and the eye pass's equiangular single scattering both peak). A closed
// grey room (ρ 0.5, 1 m) lit by a small area light under its ceiling (a point light in a medium
// gives the path tracer heavy-tailed samples, ∝ 1/D for a segment passing at D from it: one
// seed's 1024 spp read 0.63 where four others read 0.44-0.48), filled with one medium; progressive photon mapping against the reference path tracer, whole
// image means (the test's statement of "stable": finite, unbiased to within a few percent at
// small photon counts).
#include "stability/stability_common.h"

using namespace pcl;
using namespace pcl::stability;

namespace {

Scene fogRoom(Vec3 sigmaA, Vec3 sigmaS, float g) {
    Scene s;
    s.meshes.push_back(test::closedBox(0.5f, test::addMaterial(s, Vec3(0.5f))));
    test::addAreaLight(s, 0.45f, 0.12f, Vec3(12.0f));
    Medium m;
    m.name = "fog";
    m.sigmaA = sigmaA;
    m.sigmaS = sigmaS;
    m.g = g;
    s.media.push_back(m);
    s.globalMedium = 0;
    s.camera.position = Vec3(0.0f, 0.0f, 0.45f);
    s.camera.lookAt = Vec3(0.0f, -0.05f, -0.5f);
    s.camera.vfovDegrees = 70.0f;
    s.camera.width = s.camera.height = 24;
    validateScene(s);
    return s;
}

}  // namespace

TEST(MediaStability, ThinDenseForwardAndBackwardFogMatchThePathTracer) {
    struct Case {
        const char* name;
        Vec3 sigmaA, sigmaS;
        float g;
        double tolerance;
    };
    const Case cases[] = {
        {"thin", Vec3(0.01f), Vec3(0.05f), 0.0f, 0.03},
        {"dense", Vec3(0.5f), Vec3(8.0f), 0.3f, 0.05},
        {"forward g 0.9", Vec3(0.05f), Vec3(1.5f), 0.9f, 0.04},
        {"backward g -0.9", Vec3(0.05f), Vec3(1.5f), -0.9f, 0.04},
    };
    for (const Case& c : cases) {
        auto p = prepare(fogRoom(c.sigmaA, c.sigmaS, c.g));
        PhotonRenderSettings s;
        s.passes = 16;
        s.strata = 2;
        s.globalPhotons = 40000;
        s.causticPhotons = 0;
        s.seed = 7;
        const Image pm = test::renderImage(*p, RenderMethod::Progressive, s, 0, 0, c.name);
        const Image pt = test::renderImage(*p, RenderMethod::PathTracing, s, 1024, 3, c.name);
        const double ratio = channelSum(pm) / channelSum(pt);
        std::printf("[figure] media %s: progressive / path tracer mean %.4f (bound %.0f %%), path mean %.4f\n", c.name,
                    ratio, 100.0 * c.tolerance, channelSum(pt) / double(pt.rgb.size()));
        EXPECT_NEAR(ratio, 1.0, c.tolerance) << c.name;
    }
}
