// Estimates at the eye hits (kernels/eye_estimate.cl): caustics from the caustic map and the
// direct-visualisation preview from the global map, against the twin (reference/eye_estimate);
// a constant irradiance gives L = T ρ E/π exactly; the furnace's preview reads ρ/(1 − ρ); a
// ceiling mirror's caustic on the floor matches its image light.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "check/on_device.h"
#include "check/render.h"
#include "eye_test_scenes.h"
#include "pipeline/eye_estimate.h"
#include "pipeline/photon_pass.h"
#include "reference/eye_estimate.h"

namespace pcl {
namespace {

PclEyeEstimateParams estimateParams(size_t n, uint32_t k, float rMax) {
    PclEyeEstimateParams p{};
    p.sampleCount = uint32_t(n);
    p.k = k;
    p.maxRadius2 = rMax * rMax;
    return p;
}

TEST(EyeEstimate, CausticsAndPreviewMatchTheTwinCornellSpheres) {
    const test::BuiltScene b = test::shippedScene("cornell-spheres.json", 40, 30);
    PhotonPassOptions po;
    po.globalPhotons = 20000;
    po.causticPhotons = 20000;
    const PhotonMaps maps = runPhotonPass(test::testDevice(), b.geometry, b.buffers, po);
    ASSERT_GT(maps.caustic.size(), 1000u);
    const std::vector<PclEyeHit> hits = test::deviceEyeHits(b, 2, 8);
    const float rMax = 0.1f * length(b.geometry.bounds().extent());
    const PclEyeEstimateParams p = estimateParams(hits.size(), 50, rMax);
    EstimateSettings es;
    es.rayEpsilon = b.buffers.rayEpsilon;
    for (int which = 0; which < 2; ++which) {
        const std::vector<PclPhoton>& photons = which == 0 ? maps.caustic : maps.global;
        PhotonMapOnDevice map(test::testDevice(), photons, KnnStructure::KdTree, rMax);
        auto source = estimateIrradianceSource(map, 50, es, nullptr);
        const EyeEstimateResult d = estimateAtEyeHitsOnDevice(test::testDevice(), hits, p, *source);
        const std::vector<PclRadiance> t =
            referenceEstimateAtEyeHits(hits, p, {}, referenceEstimateIrradiance(photons, es, nullptr));
        const StageComparison c = compareRadiance(which == 0 ? "caustics" : "preview", d.radiance, t, 1e-3, 3);
        std::printf("[figure] %s at the eye hits, cornell-spheres 40x30 2x2, %zu photons: %.4f %% of %zu within 1e-3 "
                    "(%zu nonzero), max rel %.3e, %zu NaN/Inf\n",
                    which == 0 ? "caustics" : "direct visualisation", photons.size(), 100.0 * c.fraction(), c.compared,
                    c.nonzero, c.maxRelError, c.nonFinite);
        EXPECT_GE(c.fraction(), 0.999);
        EXPECT_EQ(c.nonFinite, 0u);
        EXPECT_GT(c.nonzero, which == 0 ? c.compared / 20 : c.compared / 2);
    }
}

// The global map keeps a moving surface's photons where it sits at shutter open
// (kernels/shared/shutter_open.h): with atShutterOpen a hit on motion-dof's moving ball asks at
// p − m τ (its own time τ), every other hit at p, device and twin alike; without, every hit at p.
TEST(EyeEstimate, GlobalQueriesOnAMovingSurfaceAskWhereItSitsAtShutterOpen) {
    const test::BuiltScene b = test::shippedScene("motion-dof.json", 48, 36);
    const std::vector<PclEyeHit> hits = test::deviceEyeHits(b, 2, 8);
    IrradianceSource e = test::constantIrradiance(1.0f);
    for (uint32_t atShutterOpen : {0u, 1u}) {
        PclEyeEstimateParams p = estimateParams(hits.size(), 10, 0.1f);
        p.atShutterOpen = atShutterOpen;
        const EyeEstimateResult d = estimateAtEyeHitsOnDevice(test::testDevice(), hits, p, e, b.buffers.primInfo);
        const std::vector<PclEstimateQuery> t = referenceEyeEstimateQueries(hits, p, b.buffers.primInfo);
        size_t moving = 0, wrong = 0;
        for (size_t i = 0; i < hits.size(); ++i) {
            const PclEyeHit& h = hits[i];
            if (!(h.flags & PCL_EYE_DIFFUSE)) continue;
            const PclPrimInfo& info = b.buffers.primInfo[h.prim];
            const bool moves = info.mx != 0.0f || info.my != 0.0f || info.mz != 0.0f;
            moving += moves;
            const float tau = atShutterOpen ? h.time : 0.0f;
            const float x = h.x - info.mx * tau, y = h.y - info.my * tau, z = h.z - info.mz * tau;
            if (d.queries[i].x != x || d.queries[i].y != y || d.queries[i].z != z) ++wrong;
            if (t[i].x != x || t[i].y != y || t[i].z != z) ++wrong;
        }
        std::printf("[figure] motion-dof eye hits, atShutterOpen %u: %zu of %zu on the moving ball, %zu queries "
                    "elsewhere than expected\n",
                    atShutterOpen, moving, hits.size(), wrong);
        EXPECT_GT(moving, hits.size() / 50);
        EXPECT_EQ(wrong, 0u);
    }
}

TEST(EyeEstimate, ConstantIrradianceGivesThroughputAlbedoEOverPi) {
    const test::BuiltScene b = test::shippedScene("cornell-glossy.json", 24, 18);
    const std::vector<PclEyeHit> hits = test::deviceEyeHits(b, 1, 5);
    IrradianceSource e = test::constantIrradiance(2.5f);
    const EyeEstimateResult d =
        estimateAtEyeHitsOnDevice(test::testDevice(), hits, estimateParams(hits.size(), 10, 0.1f), e);
    double worst = 0.0;
    for (size_t i = 0; i < hits.size(); ++i) {
        const PclEyeHit& h = hits[i];
        const double expect = (h.flags & PCL_EYE_DIFFUSE) ? h.throughput[1] * h.albedo[1] * 2.5 / M_PI : 0.0;
        worst = std::max(worst, std::fabs(d.radiance[i].g - expect) / std::max(expect, 1e-30));
        if (!(h.flags & PCL_EYE_DIFFUSE)) {
            EXPECT_EQ(d.queries[i].maxRadius2, 0.0f);
        }
    }
    std::printf("[figure] constant E at the eye hits: L = T ρ E/π within %.2e relative\n", worst);
    EXPECT_LT(worst, 1e-6);
}

TEST(EyeEstimate, FurnacePreviewReadsRhoOverOneMinusRho) {
    for (const char* name : {"furnace-0.5.json", "furnace-0.8.json"}) {
        const test::BuiltScene b = test::shippedScene(name, 16, 16);
        const float rho = b.scene.materials[0].rhoD.x;
        PhotonPassOptions po;
        po.globalPhotons = 40000;
        po.buildCaustic = false;
        const PhotonMaps maps = runPhotonPass(test::testDevice(), b.geometry, b.buffers, po);
        const std::vector<PclEyeHit> hits = test::deviceEyeHits(b, 2, 3);
        EstimateSettings es;
        PhotonMapOnDevice map(test::testDevice(), maps.global, KnnStructure::KdTree, 0.3f);
        auto source = estimateIrradianceSource(map, 50, es, nullptr);
        const EyeEstimateResult d =
            estimateAtEyeHitsOnDevice(test::testDevice(), hits, estimateParams(hits.size(), 50, 0.3f), *source);
        const double mean = test::meanLuminance(d.radiance), expect = rho / (1.0 - rho);
        std::printf("[figure] furnace %s preview (global map at the eye hits, k 50): mean %.4f vs %.4f (%+.2f %%)\n",
                    name, mean, expect, 100.0 * (mean / expect - 1.0));
        EXPECT_NEAR(mean / expect, 1.0, 0.02);
    }
}

}  // namespace
}  // namespace pcl

namespace pcl {
namespace {

// Caustics, analytically: a point light between a diffuse floor (y = 0) and a ceiling mirror
// (y = 3, ρs = 1) lights the floor through the mirror as a point light of the same intensity at
// its image (0, 4, 0): E_c = I cosθ'/d'², so the caustic radiance is ρd/π E_c.
TEST(EyeEstimate, MirrorCausticMatchesTheImageLight) {
    Scene s;
    s.camera.position = Vec3(0, 2.5f, 3);
    s.camera.lookAt = Vec3(0.0f);
    s.camera.width = s.camera.height = 8;
    const int floor = test::addMaterial(s, Vec3(0.5f));
    const int mirror = test::addMaterial(s, Vec3(0.0f), Vec3(1.0f), SpecularKind::Mirror);
    TriangleMesh f;
    f.material = floor;
    test::addQuad(f, Vec3(-6, 0, -6), Vec3(-6, 0, 6), Vec3(6, 0, 6), Vec3(6, 0, -6));
    s.meshes.push_back(f);
    TriangleMesh m;
    m.material = mirror;
    test::addQuad(m, Vec3(-6, 3, -6), Vec3(6, 3, -6), Vec3(6, 3, 6), Vec3(-6, 3, 6));
    s.meshes.push_back(m);
    const float I = 10.0f;
    s.lights.push_back(test::pointLight(Vec3(0, 2, 0), Vec3(I)));
    test::BuiltScene b = test::build(s);
    buildProjectionMaps(b.scene, b.geometry, b.buffers);
    PhotonPassOptions po;
    po.globalPhotons = 1000;
    po.causticPhotons = 400000;
    po.buildGlobal = false;
    const PhotonMaps maps = runPhotonPass(test::testDevice(), b.geometry, b.buffers, po);
    ASSERT_GT(maps.caustic.size(), 50000u);
    std::vector<PclEyeHit> hits;
    for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 9; ++j)
            hits.push_back(test::handMadeHit(Vec3(0.25f * (i - 4), 0.0f, 0.25f * (j - 4)), Vec3(0, 1, 0), 0.5f,
                                             uint32_t(hits.size()), 0));
    PhotonMapOnDevice map(test::testDevice(), maps.caustic, KnnStructure::KdTree, 0.5f);
    auto source = estimateIrradianceSource(map, 200, EstimateSettings{}, nullptr);
    const EyeEstimateResult d =
        estimateAtEyeHitsOnDevice(test::testDevice(), hits, estimateParams(hits.size(), 200, 0.5f), *source);
    double sum = 0.0, sumExpect = 0.0, worst = 0.0;
    for (size_t i = 0; i < hits.size(); ++i) {
        const Vec3 p(hits[i].x, hits[i].y, hits[i].z);
        const Vec3 toImage = Vec3(0, 4, 0) - p;
        const double d2 = dot(toImage, toImage), cosT = toImage.y / std::sqrt(d2);
        const double expect = 0.5 / M_PI * I * cosT / d2;
        sum += d.radiance[i].r;
        sumExpect += expect;
        worst = std::max(worst, std::fabs(d.radiance[i].r / expect - 1.0));
    }
    std::printf("[figure] mirror caustic (%zu caustic photons, k 200): mean over 81 floor points %.5f vs image light "
                "%.5f (%+.2f %%), worst point %.2f %%\n",
                maps.caustic.size(), sum / hits.size(), sumExpect / hits.size(), 100.0 * (sum / sumExpect - 1.0),
                100.0 * worst);
    EXPECT_NEAR(sum / sumExpect, 1.0, 0.02);
    EXPECT_LT(worst, 0.35);  // one point of 81 at about 4σ of a k = 200 estimate
}

}  // namespace
}  // namespace pcl
