// Final gathering (kernels/final_gather.cl) against the twin (reference/final_gather), and
// analytic checks: the furnace (a point light of π W/sr at the centre of a closed unit sphere of
// albedo ρ: L = ρ/(1 − ρ) everywhere) with the exact irradiance plugged in (direct + gather per
// sample), with the global photon map's estimate and with precomputed irradiance (means); and
// MIS: direct light's area samples plus the emitters the gather rays hit add up to the square
// light's exact irradiance; gather rays leaving glass carry radiance × η²; close gather hits
// (direct light by shadow rays, the map's photons that bounced for the rest) match the twin under
// every kind of light (the sky's caustics left to the gather rays) and keep the furnace's mean.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "check/on_device.h"
#include "check/render.h"
#include "eye_test_scenes.h"
#include "pipeline/direct_light.h"
#include "pipeline/final_gather.h"
#include "pipeline/photon_pass.h"
#include "pipeline/precomputed_irradiance.h"
#include "reference/final_gather.h"
#include "reference/precomputed_irradiance.h"

namespace pcl {
namespace {

struct Stages {
    PclEyeParams ep{};
    PclDirectParams dp{};
    PclGatherParams gp{};
    std::vector<PclEyeHit> hits;
};

Stages prepare(const test::BuiltScene& b, uint32_t strata, uint32_t M, uint32_t N, uint32_t k, float rMax) {
    Stages s;
    s.hits = test::deviceEyeHits(b, strata, eyePassSeed(2, 0), &s.ep);
    const AreaLightTable table = buildAreaLightTable(b.buffers, b.geometry.primitiveCount());
    s.dp = directParams(s.ep, b.geometry, b.buffers, table, M, N);
    if (N > 0) s.gp = gatherParams(s.dp, N, k, rMax * rMax);
    return s;
}

TEST(FinalGather, DeviceMatchesTwinCornellGlossy) {
    const test::BuiltScene b = test::shippedScene("cornell-glossy.json", 32, 24);
    PhotonPassOptions po;
    po.globalPhotons = 20000;
    po.buildCaustic = false;
    const PhotonMaps maps = runPhotonPass(test::testDevice(), b.geometry, b.buffers, po);
    const float rMax = 0.1f * length(b.geometry.bounds().extent());
    const Stages s = prepare(b, 1, 1, 8, 50, rMax);
    EstimateSettings es;
    es.rayEpsilon = b.buffers.rayEpsilon;
    PhotonMapOnDevice map(test::testDevice(), maps.global, KnnStructure::KdTree, rMax);
    DeviceScene ds(test::testDevice(), b.geometry, b.buffers);
    auto source = estimateIrradianceSource(map, 50, es, &ds);
    const GatherResult d = finalGatherOnDevice(test::testDevice(), b.geometry, b.buffers, s.hits, s.gp, *source);
    const ReferenceGather t = referenceFinalGather(b.geometry, b.buffers, s.hits, s.gp,
                                                   referenceEstimateIrradiance(maps.global, es, &b.geometry));
    const StageComparison c = compareRadiance("gather", d.radiance, t.radiance, 1e-3, 3);
    std::vector<float> dg, tg;
    for (size_t j = 0; j < d.gathered.size(); ++j)
        for (int k = 0; k < 3; ++k) {
            dg.insert(dg.end(), {d.gathered[j].weight[k], d.gathered[j].emitted[k]});
            tg.insert(tg.end(), {t.gathered[j].weight[k], t.gathered[j].emitted[k]});
        }
    const StageComparison rays = compareValues("gather rays", dg, tg, 6, 1e-3, 3);
    std::printf("[figure] final gather cornell-glossy 32x24 N=8: radiance %.4f %% of %zu within 1e-3 (max rel %.3e), "
                "gather rays %.4f %% of %zu (max rel %.3e), NaN/Inf %zu\n",
                100.0 * c.fraction(), c.compared, c.maxRelError, 100.0 * rays.fraction(), rays.compared,
                rays.maxRelError, c.nonFinite + rays.nonFinite);
    EXPECT_GE(c.fraction(), 0.999);
    EXPECT_GE(rays.fraction(), 0.999);
    EXPECT_EQ(c.nonFinite + rays.nonFinite, 0u);
}

// Close gather hits (params.closeDistance): direct light there by shadow rays, the map's other
// photons (PCL_QUERY_NONDIRECT) for the rest, under a triangle light, a point light and a sky;
// device and twin through the full estimate and through precomputed irradiance.
TEST(FinalGather, CloseHitsMatchTheTwinUnderAreaPointAndSkyLight) {
    for (const char* name : {"cornell-glossy.json", "cornell-spheres-point.json", "sky-spheres.json"}) {
        const test::BuiltScene b = test::shippedScene(name, 32, 24);
        PhotonPassOptions po;
        po.globalPhotons = 20000;
        po.buildCaustic = false;
        const PhotonMaps maps = runPhotonPass(test::testDevice(), b.geometry, b.buffers, po);
        const float rMax = 0.1f * length(b.geometry.bounds().extent());
        Stages s = prepare(b, 1, 1, 8, 50, rMax);
        s.gp.closeDistance = 3.0f * rMax;
        // As fg renders them: the caustic map read at the eye hits, the sky's caustics left to
        // the gather rays (it sent no caustic photons): rays escaping after glass count.
        s.gp.causticMapRead = 1;
        s.gp.causticSky = 0;
        EstimateSettings es;
        es.rayEpsilon = b.buffers.rayEpsilon;
        PhotonMapOnDevice map(test::testDevice(), maps.global, KnnStructure::KdTree, rMax);
        DeviceScene ds(test::testDevice(), b.geometry, b.buffers);
        auto full = estimateIrradianceSource(map, 50, es, &ds);
        const GatherResult d = finalGatherOnDevice(test::testDevice(), b.geometry, b.buffers, s.hits, s.gp, *full);
        const ReferenceGather t = referenceFinalGather(b.geometry, b.buffers, s.hits, s.gp,
                                                       referenceEstimateIrradiance(maps.global, es, &b.geometry));
        size_t close = 0, flagsDiffer = 0;
        for (size_t j = 0; j < d.queries.size(); ++j) {
            close += (t.queries[j].k & PCL_QUERY_NONDIRECT) != 0;
            flagsDiffer += d.queries[j].k != t.queries[j].k;
        }
        const StageComparison c = compareRadiance("gather", d.radiance, t.radiance, 1e-3, 3);

        PrecomputedIrradianceOptions pio;
        pio.maxRadius = rMax;
        pio.estimate = es;
        const DeviceIrradianceMap irr = precomputeIrradiance(test::testDevice(), maps.global, pio, &ds);
        auto pre = precomputedIrradianceSource(irr);
        const GatherResult dp = finalGatherOnDevice(test::testDevice(), b.geometry, b.buffers, s.hits, s.gp, *pre);
        const std::vector<PclIrradiancePoint> points = downloadIrradiancePoints(test::testDevice(), irr);
        const std::vector<float> cover = downloadIrradianceCover(test::testDevice(), irr);
        const std::vector<float> later = downloadIrradianceNondirect(test::testDevice(), irr);
        const ReferenceGather tp =
            referenceFinalGather(b.geometry, b.buffers, s.hits, s.gp,
                                 referencePrecomputedIrradiance(points, cover, irr.minNormalCos, later));
        const StageComparison cp = compareRadiance("gather (precomp.)", dp.radiance, tp.radiance, 1e-3, 3);
        std::printf("[figure] close gather hits, %s 32x24 N=8, closeDistance %.3f: %zu of %zu rays close; radiance "
                    "%.4f %% (estimate) and %.4f %% (precomputed) within 1e-3 of the twin, NaN/Inf %zu\n",
                    name, double(s.gp.closeDistance), close, t.queries.size(), 100.0 * c.fraction(),
                    100.0 * cp.fraction(), c.nonFinite + cp.nonFinite);
        EXPECT_GT(close, t.queries.size() / 50) << name;
        EXPECT_EQ(flagsDiffer, 0u) << name;
        // The full estimate's normal test (n_p·n_q ≥ 0.9) on the spheres can flip for a photon
        // whose dot lies an ulp from the threshold: one record of 768 read 9 photons, not 10.
        EXPECT_GE(c.fraction(), 0.995) << name;
        EXPECT_GE(cp.fraction(), 0.999) << name;
        EXPECT_EQ(c.nonFinite + cp.nonFinite, 0u) << name;
    }
}

std::vector<PclRadiance> directOf(const test::BuiltScene& b, const Stages& s) {
    return directLightOnDevice(test::testDevice(), b.geometry, b.buffers, s.hits, s.dp);
}

TEST(FinalGather, FurnaceWithExactIrradianceIsRhoOverOneMinusRhoPerSample) {
    for (const char* name : {"furnace-0.5.json", "furnace-0.8.json"}) {
        const test::BuiltScene b = test::shippedScene(name, 16, 16);
        const float rho = b.scene.materials[0].rhoD.x;
        const Stages s = prepare(b, 1, 1, 16, 50, 0.1f);
        IrradianceSource exact = test::constantIrradiance(float(M_PI) / (1.0f - rho));  // E everywhere
        const GatherResult g = finalGatherOnDevice(test::testDevice(), b.geometry, b.buffers, s.hits, s.gp, exact);
        const std::vector<PclRadiance> direct = directOf(b, s);
        const double expect = rho / (1.0 - rho);
        double worst = 0.0;
        for (size_t i = 0; i < s.hits.size(); ++i) {
            ASSERT_TRUE(s.hits[i].flags & PCL_EYE_DIFFUSE);
            worst = std::max(worst, std::fabs((direct[i].g + g.radiance[i].g) / expect - 1.0));
        }
        std::printf("[figure] furnace %s, exact irradiance at the gather hits: direct + gather = ρ/(1−ρ) = %.3f within "
                    "%.2e relative on every sample\n",
                    name, expect, worst);
        EXPECT_LT(worst, 1e-5);
    }
}

TEST(FinalGather, FurnaceWithThePhotonMapAndPrecomputedIrradiance) {
    for (const char* name : {"furnace-0.5.json", "furnace-0.8.json"}) {
        const test::BuiltScene b = test::shippedScene(name, 16, 16);
        const float rho = b.scene.materials[0].rhoD.x;
        PhotonPassOptions po;
        po.globalPhotons = 40000;
        po.buildCaustic = false;
        const PhotonMaps maps = runPhotonPass(test::testDevice(), b.geometry, b.buffers, po);
        const float rMax = 0.3f;
        Stages s = prepare(b, 2, 1, 16, 50, rMax);
        const std::vector<PclRadiance> direct = directOf(b, s);
        EstimateSettings es;
        es.rayEpsilon = b.buffers.rayEpsilon;
        PhotonMapOnDevice map(test::testDevice(), maps.global, KnnStructure::KdTree, rMax);
        auto full = estimateIrradianceSource(map, 50, es, nullptr);
        PrecomputedIrradianceOptions pio;
        pio.maxRadius = rMax;
        pio.estimate = es;
        const DeviceIrradianceMap irr = precomputeIrradiance(test::testDevice(), maps.global, pio, nullptr);
        auto pre = precomputedIrradianceSource(irr);
        const double expect = rho / (1.0 - rho);
        // closeDistance 10: every gather hit is close (direct light by shadow rays, the map's
        // photons of bounce > 0 for the rest); counting the direct photons there too would read
        // ρ too high.
        for (float closeDistance : {0.0f, 10.0f})
            for (IrradianceSource* src : {full.get(), pre.get()}) {
                s.gp.closeDistance = closeDistance;
                const GatherResult g =
                    finalGatherOnDevice(test::testDevice(), b.geometry, b.buffers, s.hits, s.gp, *src);
                double sum = 0.0;
                size_t bad = 0;
                for (size_t i = 0; i < s.hits.size(); ++i) {
                    const double L = (direct[i].r + g.radiance[i].r + direct[i].g + g.radiance[i].g + direct[i].b +
                                      g.radiance[i].b) /
                                     3.0;
                    bad += !std::isfinite(L);
                    sum += L;
                }
                const double mean = sum / double(s.hits.size());
                std::printf("[figure] furnace %s, %zu global photons, %s, close gather %s: mean L %.4f vs ρ/(1−ρ) %.4f "
                            "(%+.2f %%)\n",
                            name, maps.global.size(), src->name.c_str(), closeDistance > 0.0f ? "all" : "none", mean,
                            expect, 100.0 * (mean / expect - 1.0));
                EXPECT_EQ(bad, 0u);
                EXPECT_NEAR(mean / expect, 1.0, 0.02);
            }
    }
}

TEST(FinalGather, MisHalvesAddUpToTheSquareLight) {
    Scene sc;
    sc.camera.position = Vec3(0, 5, 5);
    sc.camera.width = sc.camera.height = 8;
    const int floor = test::addMaterial(sc, Vec3(0.5f));
    TriangleMesh m;
    m.material = floor;
    // A small floor: the spawn offset (1e-4 of the scene's diagonal) lifts the gather rays'
    // origins, and a lifted origin sees the light larger (+2 % with a 100 m floor).
    test::addQuad(m, Vec3(-2, 0, -2), Vec3(-2, 0, 2), Vec3(2, 0, 2), Vec3(2, 0, -2));
    sc.meshes.push_back(m);
    const float h = 1.0f, a = 0.5f, Le = 2.0f;
    test::addAreaLight(sc, h, a, Vec3(Le));
    const test::BuiltScene b = test::build(sc);
    Stages s;
    for (uint32_t i = 0; i < 40000; ++i) s.hits.push_back(test::handMadeHit(Vec3(0.0f), Vec3(0, 1, 0), 0.5f, i, 0));
    s.ep.samplesPerPixel = 1;
    s.ep.sampleCount = uint32_t(s.hits.size());
    s.ep.seedLo = 99;
    const AreaLightTable table = buildAreaLightTable(b.buffers, b.geometry.primitiveCount());
    const double A = a / h, sa = std::sqrt(1 + A * A);
    const double expect = 0.5 / M_PI * 4.0 * M_PI * Le * (1.0 / M_PI) * (A / sa * std::atan(A / sa));
    IrradianceSource zero = test::constantIrradiance(0.0f);
    const uint32_t configs[][2] = {{2, 4}, {2, 16}, {0, 16}};  // (M, N); M = 0: the gather rays alone
    for (const auto& mn : configs) {
        const uint32_t M = mn[0], N = mn[1];
        s.dp = directParams(s.ep, b.geometry, b.buffers, table, M, N);
        s.gp = gatherParams(s.dp, N, 10, 0.01f);
        const double light = test::meanLuminance(directOf(b, s));
        const double bsdf = test::meanLuminance(
            finalGatherOnDevice(test::testDevice(), b.geometry, b.buffers, s.hits, s.gp, zero).radiance);
        std::printf("[figure] MIS M=%u N=%u: light half %.5f + BSDF half %.5f = %.5f vs analytic %.5f (%+.3f %%)\n", M,
                    N, light, bsdf, light + bsdf, expect, 100.0 * ((light + bsdf) / expect - 1.0));
        EXPECT_GT(bsdf, 0.0);
        EXPECT_NEAR((light + bsdf) / expect, 1.0, 0.01);
    }
}

// Gather rays are radiance paths too (η² across a refraction, kernels/README.md "eye paths"):
// from a point at the centre of a glass sphere (radius 1, η 1.5, ρs 1) every gather ray leaves
// at normal incidence, refracted (radiance into the glass × η² = 2.25) or reflected back through
// the centre and out the far side, and ends on a diffuse shell (radius 3, ρw 0.5) where the
// irradiance is E = π: each sample reads L = ρd η² ρw E/π = 0.5625 (without the factor: 0.25).
// A ray still reflecting after maxSpecular (4) events ends with nothing: F⁴ ≈ 2.6e-6 of them.
// Device and twin alike; every sample within 1e-5 relative (float sums of 16 equal terms).
TEST(FinalGather, GatherFromInsideGlassScalesByEtaSquared) {
    Scene sc;
    sc.camera.width = sc.camera.height = 8;
    const int glass = test::addMaterial(sc, Vec3(0.0f), Vec3(1.0f), SpecularKind::Dielectric, 0.0f, 1.5f);
    const int shell = test::addMaterial(sc, Vec3(0.5f));
    for (const auto& [radius, material] : {std::pair<float, int>{1.0f, glass}, {3.0f, shell}}) {
        Sphere sp;
        sp.centre = Vec3(0.0f);
        sp.radius = radius;
        sp.material = material;
        sc.spheres.push_back(sp);
    }
    sc.lights.push_back(test::pointLight(Vec3(0, 2, 0), Vec3(1.0f)));
    const test::BuiltScene b = test::build(sc);
    Stages s;
    for (uint32_t i = 0; i < 1024; ++i) s.hits.push_back(test::handMadeHit(Vec3(0.0f), Vec3(0, 0, 1), 0.5f, i, 0));
    s.ep.samplesPerPixel = 1;
    s.ep.sampleCount = uint32_t(s.hits.size());
    s.ep.seedLo = 7;
    const AreaLightTable table = buildAreaLightTable(b.buffers, b.geometry.primitiveCount());
    s.dp = directParams(s.ep, b.geometry, b.buffers, table, 0, 16);
    s.gp = gatherParams(s.dp, 16, 10, 0.01f);
    const float E = float(M_PI);
    IrradianceSource constant = test::constantIrradiance(E);
    const GatherResult d = finalGatherOnDevice(test::testDevice(), b.geometry, b.buffers, s.hits, s.gp, constant);
    const ReferenceGather t =
        referenceFinalGather(b.geometry, b.buffers, s.hits, s.gp, [E](const std::vector<PclEstimateQuery>& q) {
            return std::vector<Vec3>(q.size(), Vec3(E));
        });
    const double expect = 0.5 * 1.5 * 1.5 * 0.5 * E / M_PI;
    for (const auto& [name, radiance] :
         {std::pair<const char*, const std::vector<PclRadiance>*>{"device", &d.radiance}, {"twin", &t.radiance}}) {
        double worst = 0.0;
        for (const PclRadiance& r : *radiance)
            for (float v : {r.r, r.g, r.b}) worst = std::max(worst, std::fabs(v / expect - 1.0));
        std::printf("[figure] gather from inside glass, %s: every sample ρd η² ρw E/π = %.4f within %.2e relative\n",
                    name, expect, worst);
        EXPECT_LT(worst, 1e-5) << name;
    }
}

}  // namespace
}  // namespace pcl
