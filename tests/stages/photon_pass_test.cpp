// The whole device photon pass (pipeline/photon_pass) on every shipped scene, with projection
// maps: emitted flux equals the lights' power (1e-4), every path ends one way, every record is
// well formed (inside the scene, flags and bounce consistent with its map), no record carries
// more power than its photon left the light with (up to RGBE rounding and the Phong lobe's
// (n+2)/(n+1)), and every scene whose lights reach a specular surface, mixed ones included,
// gets a non-empty caustic map.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "check/on_device.h"
#include "device_fixture.h"
#include "photon_test_scenes.h"
#include "pipeline/photon_pass.h"
#include "prep/photon_allocation.h"
#include "prep/projection_map.h"

namespace pcl {
namespace {

double maxDecoded(const PclPhoton& p) {
    uint32_t e = p.rgbe >> 24;
    if (e == 0) return 0.0;
    uint32_t m = std::max(p.rgbe & 255u, std::max((p.rgbe >> 8) & 255u, (p.rgbe >> 16) & 255u));
    return std::ldexp(double(m), int(e) - 136);
}

void checkScene(const std::string& path) {
    SCOPED_TRACE(path);
    const test::ScenePhotonPass pass = test::runScenePhotonPass(path, 20000, 5);
    const SceneGeometry& geometry = pass.built.geometry;
    const SceneBuffers& buffers = pass.built.buffers;
    const PhotonPassOptions& o = pass.options;
    const PhotonMaps& maps = pass.maps;
    std::printf("%s\n%s", std::filesystem::path(path).filename().c_str(), maps.stats.summary().c_str());

    double want[3] = {0, 0, 0}, wantCaustic[3] = {0, 0, 0};
    double maxPerPhoton = 0, maxPerCaustic = 0;
    std::vector<uint32_t> first = lightFirstPhoton(buffers, o.globalPhotons, PCL_PASS_GLOBAL);
    std::vector<uint32_t> firstC = lightFirstPhoton(buffers, o.causticPhotons, PCL_PASS_CAUSTIC);
    bool anyMarked = false;
    for (size_t l = 0; l < buffers.lights.size(); ++l) {
        const PclLight& L = buffers.lights[l];
        double f = projectionFraction(L);
        anyMarked |= L.projCount > 0;
        for (int c = 0; c < 3; ++c) {
            want[c] += L.power[c];
            wantCaustic[c] += L.power[c] * f;
            if (first[l + 1] > first[l])
                maxPerPhoton = std::max(maxPerPhoton, double(L.power[c]) / (first[l + 1] - first[l]));
            if (firstC[l + 1] > firstC[l])
                maxPerCaustic = std::max(maxPerCaustic, double(L.power[c]) * f / (firstC[l + 1] - firstC[l]));
        }
    }
    const PhotonPassKindStats& g = maps.stats.global;
    const PhotonPassKindStats& c = maps.stats.caustic;
    // The flux the device's rays carry, summed from the rays emit_photons wrote (the same
    // photons, seeds and allocation as the pass), against the closed form Σ Φ_l (caustic: Σ Φ_l
    // f_l) and against the pass's own account (stats.emittedFlux, computed on the host).
    const uint64_t passSeed = photonPassSeed(o.seed, o.pass);
    double rayFlux[2][3] = {{0, 0, 0}, {0, 0, 0}};
    for (const uint32_t kind : {uint32_t(PCL_PASS_GLOBAL), uint32_t(PCL_PASS_CAUSTIC)}) {
        const std::vector<uint32_t>& f = kind == PCL_PASS_GLOBAL ? first : firstC;
        if (f.back() == 0) continue;
        const PclPhotonParams params = makePhotonParams(geometry, buffers, kind, passSeed, o.maxDepth, 0, f.back());
        for (const PclPhotonRay& r : emitOnDevice(test::testDevice(), geometry, buffers, f, params))
            for (int k = 0; k < 3; ++k) rayFlux[kind == PCL_PASS_CAUSTIC][k] += r.power[k];
    }
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(rayFlux[0][k], want[k], 1e-4 * want[k]) << "global rays, channel " << k;
        EXPECT_NEAR(rayFlux[1][k], wantCaustic[k], 1e-4 * want[k]) << "caustic rays, channel " << k;
        EXPECT_NEAR(g.emittedFlux[k], rayFlux[0][k], 1e-4 * want[k]);
        EXPECT_NEAR(c.emittedFlux[k], rayFlux[1][k], 1e-4 * want[k]);
    }
    EXPECT_EQ(g.emitted, o.globalPhotons);
    EXPECT_EQ(g.escaped + g.absorbed + g.maxDepth + g.stored, g.emitted);
    EXPECT_EQ(g.stored, 0u);
    EXPECT_EQ(c.escaped + c.absorbed + c.maxDepth + c.stored, c.emitted);
    // STORED counts caustic paths that ended at a hit they deposited at: a path deposits at
    // least once before so ending, and more often only through mixed surfaces.
    EXPECT_LE(c.stored, maps.caustic.size());
    EXPECT_EQ(g.deposits, maps.global.size());
    EXPECT_GT(maps.global.size(), o.globalPhotons / 4);
    // Marked cells mean a light reaches a specular surface; in every shipped scene that one sees
    // a diffuse surface (or has a diffuse part seen by another specular one), so LS+D paths exist:
    // a mixed glossy floor bounces caustic photons on specularly (kernels/README.md, step 1).
    if (anyMarked) {
        EXPECT_EQ(c.emitted, o.causticPhotons);
        EXPECT_GT(maps.caustic.size(), 0u) << "specular surfaces in reach of a light but an empty caustic map";
        EXPECT_GE(c.stored, 1u);
    } else {
        EXPECT_EQ(c.emitted, 0u);
        EXPECT_TRUE(maps.caustic.empty());
    }

    Bounds3 bounds = geometry.bounds();
    const float slack = 1e-3f * length(bounds.extent());
    auto inside = [&](const PclPhoton& p) {
        return p.x >= bounds.lo.x - slack && p.x <= bounds.hi.x + slack && p.y >= bounds.lo.y - slack &&
               p.y <= bounds.hi.y + slack && p.z >= bounds.lo.z - slack && p.z <= bounds.hi.z + slack;
    };
    const double growth = 1.02 * (1.0 + 1.0 / 128.0);  // Phong (n+2)/(n+1) for n ≥ 60, RGBE rounding
    for (const PclPhoton& p : maps.global) {
        ASSERT_TRUE(inside(p)) << p.x << " " << p.y << " " << p.z;
        uint32_t bounce = (p.packed >> PCL_PHOTON_BOUNCE_SHIFT) & 0xFFu, flags = p.packed & 0xFF000000u;
        ASSERT_LT(bounce, o.maxDepth);
        ASSERT_EQ(flags & PCL_PHOTON_CAUSTIC, 0u);
        if (bounce == 0) {
            ASSERT_EQ(flags, 0u);
        } else ASSERT_NE(flags, 0u);
        ASSERT_LE(maxDecoded(p), maxPerPhoton * growth);
    }
    for (const PclPhoton& p : maps.caustic) {
        ASSERT_TRUE(inside(p));
        uint32_t bounce = (p.packed >> PCL_PHOTON_BOUNCE_SHIFT) & 0xFFu, flags = p.packed & 0xFF000000u;
        ASSERT_GE(bounce, 1u);
        ASSERT_EQ(flags, PCL_PHOTON_CAUSTIC | PCL_PHOTON_AFTER_SPECULAR);
        ASSERT_LE(maxDecoded(p), maxPerCaustic * growth);
    }
}

TEST(PhotonPass, EveryShippedSceneGivesWellFormedMaps) {
    namespace fs = std::filesystem;
    fs::path dir = fs::path(PHOTONCL_SOURCE_DIR) / "scenes";
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (e.path().extension() == ".json") files.push_back(e.path());
#ifdef PHOTONCL_HAVE_GLTF
        if (e.path().extension() == ".gltf") files.push_back(e.path());
#endif
    }
    std::sort(files.begin(), files.end());
    ASSERT_GE(files.size(), 5u);
    for (const auto& f : files) checkScene(f.string());
}

TEST(PhotonPass, RejectsAMaximumDepthTheRecordCannotHold) {
    test::BuiltScene b = test::build([] {
        Scene s;
        s.lights.push_back(test::pointLight(Vec3(0.0f), Vec3(1.0f)));
        return s;
    }());
    PhotonPassOptions o;
    o.maxDepth = 256;
    EXPECT_THROW(runPhotonPass(test::testDevice(), b.geometry, b.buffers, o), InternalError);
    o.maxDepth = 0;
    EXPECT_THROW(runPhotonPass(test::testDevice(), b.geometry, b.buffers, o), InternalError);
}

TEST(PhotonPass, AnEmptySceneLetsEveryPhotonEscape) {
    test::BuiltScene b = test::build([] {
        Scene s;
        s.lights.push_back(test::pointLight(Vec3(0.0f), Vec3(1.0f)));
        return s;
    }());
    PhotonPassOptions o;
    o.globalPhotons = 1000;
    PhotonMaps maps = runPhotonPass(test::testDevice(), b.geometry, b.buffers, o);
    EXPECT_EQ(maps.stats.global.escaped, 1000u);
    EXPECT_TRUE(maps.global.empty());
    EXPECT_TRUE(maps.caustic.empty());  // no projection cells: no caustic photons
}

}  // namespace
}  // namespace pcl
