// Volume photons in trace_photons (kernels/trace_photons.cl, media): properties with closed
// forms, on the device's photons, and the device against its twin path by path.
//  - A point light in an infinite medium (no surface within reach): every path ends absorbed, so
//    the power scattered at all events sums to Φ α/(1 − α) per channel (α = σs/σt, Σ_k α^k), and
//    the power absorbed at the events, Σ ΔΦ σa/σs, to Φ: stored + absorbed + escaped (0) =
//    emitted, exact in expectation, checked against 4 standard errors of the per-path sums. A
//    chromatic albedo exercises the per-channel free-flight weights.
//  - First scattering distances from a point light at the centre of a medium sphere (an invisible
//    boundary, vacuum outside): the exponential exp(−σt r) truncated at the radius (KS).
//  - The scattering angle between consecutive events of a path: mean cosine g (HG).
//  - The device's volume photons equal the twin's path by path (≤ 0.1 % divergent paths), on
//    these scenes and the shipped media scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "check/on_device.h"
#include "check/photon_compare.h"
#include "check/photon_stages.h"
#include "core/math.h"
#include "device_fixture.h"
#include "photon_test_scenes.h"
#include "prep/photon_allocation.h"
#include "reference/emit.h"
#include "reference/photon_pass.h"
#include "reference/trace_photons.h"
#include "scene/load_scene.h"

namespace pcl {
namespace {

constexpr uint32_t kPaths = 100000;

uint32_t bounceOf(const PclPhoton& p) { return (p.packed >> PCL_PHOTON_BOUNCE_SHIFT) & 0xFFu; }
Vec3 positionOf(const PclPhoton& p) { return {p.x, p.y, p.z}; }

// A scene lit by a point light at the origin in `medium`: filling all space (global), or the
// inside of a sphere of radius `radius` around the light with an invisible boundary.
test::BuiltScene pointInMedium(const Medium& medium, float radius, bool global) {
    Scene s;
    s.media.push_back(medium);
    if (global) {
        // Something to build a BVH over, far out of reach (e^{-σt 1e4}).
        int black = test::addMaterial(s, Vec3(0.0f));
        s.spheres.push_back({"far", Vec3(1e4f, 0.0f, 0.0f), 1.0f, black, Vec3(0.0f), -1});
        s.globalMedium = 0;
    } else {
        Material boundary;
        boundary.name = "boundary";
        boundary.interface = true;
        s.materials.push_back(boundary);
        s.spheres.push_back({"ball", Vec3(0.0f), radius, int(s.materials.size()) - 1, Vec3(0.0f), 0});
    }
    s.lights.push_back(test::pointLight(Vec3(0.0f), Vec3(1.0f / (4.0f * kPi))));  // Φ = 1 W per channel
    return test::build(s);
}

struct VolumeRun {
    PclPhotonParams params;
    std::vector<PclPhotonRay> rays;
    PhotonTraceResult device;
    ReferencePhotonBatch twin;
};

VolumeRun traceBoth(const test::BuiltScene& b, uint32_t paths, uint32_t maxDepth, uint64_t seed) {
    VolumeRun r;
    const std::vector<uint32_t> first = lightFirstPhoton(b.buffers, paths, PCL_PASS_GLOBAL);
    r.params = makePhotonParams(b.geometry, b.buffers, PCL_PASS_GLOBAL, seed, maxDepth, 0, first.back());
    EXPECT_EQ(r.params.hasMedia, 1u);
    r.rays = emitPhotonsReference(b.buffers, first, r.params);
    r.device = tracePhotonsOnDevice(test::testDevice(), b.geometry, b.buffers, r.rays, r.params);
    r.twin = tracePhotonsReference(b.buffers, b.geometry, r.params, r.rays);
    return r;
}

// Decoded RGBE power of a record, per channel.
Vec3 powerOf(const PclPhoton& p) { return referenceDecodeRgbe(p.rgbe); }

double divergentFraction(const VolumeRun& r, float radius) {
    PhotonCheckRow row;
    comparePhotonPaths(r.twin, r.device, radius, row);
    std::printf("device vs twin: %zu of %zu paths divergent (%zu count, %zu position, %zu bits, %zu rgbe), %zu+%zu "
                "records\n",
                row.divergent, row.items, row.countMismatches, row.positionMismatches, row.packedMismatches,
                row.rgbeMismatches, row.hostDeposits, row.deviceDeposits);
    return double(row.divergent) / double(std::max<size_t>(1, row.items));
}

TEST(VolumePhotons, InfiniteMediumScattersPhiAlphaOverOneMinusAlphaAndAbsorbsPhi) {
    Medium m;
    m.name = "chromatic";
    m.sigmaS = Vec3(0.8f, 0.5f, 0.2f);
    m.sigmaA = Vec3(1.0f) - m.sigmaS;  // σt = 1: albedo (0.8, 0.5, 0.2)
    m.g = 0.3f;
    test::BuiltScene b = pointInMedium(m, 0.0f, true);
    VolumeRun r = traceBoth(b, kPaths, 255, 21);
    const uint32_t S = r.device.slotsPerPath;
    ASSERT_EQ(r.device.volumeCounts.size(), r.rays.size());

    // Per path: Σ ΔΦ over its events (device records); mean and standard error over paths.
    double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
    double rounding = 0.0;  // Σ half a mantissa step of every record: RGBE's rounding error bound
    size_t surface = 0, maxDepthEnds = 0;
    for (size_t i = 0; i < r.rays.size(); ++i) {
        surface += r.device.counts[i];
        maxDepthEnds += referenceEndCause(r.device.ends[i]) == PCL_END_MAX_DEPTH;
        Vec3 path(0.0f);
        for (uint32_t k = 0; k < r.device.volumeCounts[i]; ++k) {
            const PclPhoton& p = r.device.volumeSlots[i * S + k];
            ASSERT_TRUE(p.packed & PCL_PHOTON_VOLUME);
            ASSERT_EQ(bounceOf(p), k);
            path += powerOf(p);
            rounding += std::ldexp(1.0, int(p.rgbe >> 24) - 137);
        }
        for (int c = 0; c < 3; ++c) {
            sum[c] += path[c];
            sum2[c] += double(path[c]) * path[c];
        }
    }
    EXPECT_EQ(surface, 0u) << "no surface within reach";
    EXPECT_EQ(maxDepthEnds, 0u);
    const double n = double(r.rays.size());
    for (int c = 0; c < 3; ++c) {
        const double alpha = m.sigmaS[c] / (m.sigmaS[c] + m.sigmaA[c]);
        const double expected = alpha / (1.0 - alpha);  // Φ = 1
        const double mean = sum[c];  // every path starts with Φ/N: the sum over paths estimates the total
        const double var = (sum2[c] - sum[c] * sum[c] / n) / (n - 1.0);
        const double se = std::sqrt(var * n);  // of the total Σ over paths
        // RGBE rounds each channel of a record to the nearest mantissa step of its largest
        // channel: a bias of at most half a step per record (with grey σt every path's powers
        // keep the same ratios, so the rounding does not average out in the small channels).
        const double tol = 4.0 * se + rounding;
        const double absorbed = mean * m.sigmaA[c] / m.sigmaS[c];
        std::printf("channel %d: albedo %.2f, scattered %.5f expected %.5f (se %.5f, rounding bound %.5f), absorbed "
                    "%.5f of 1\n",
                    c, alpha, mean, expected, se, rounding, absorbed);
        EXPECT_NEAR(mean, expected, tol) << "channel " << c;
        EXPECT_NEAR(absorbed, 1.0, tol * m.sigmaA[c] / m.sigmaS[c]) << "channel " << c;
    }
    EXPECT_LE(divergentFraction(r, b.buffers.sceneRadius), 0.001);
}

TEST(VolumePhotons, FirstScatteringDistancesFollowTheTruncatedExponential) {
    Medium m;
    m.name = "grey";
    m.sigmaS = Vec3(1.2f);
    m.sigmaA = Vec3(0.3f);  // σt = 1.5
    m.g = -0.4f;
    const float R = 1.0f, sigmaT = 1.5f;
    test::BuiltScene b = pointInMedium(m, R, false);
    ASSERT_EQ(b.buffers.lightMedia.size(), 1u);
    EXPECT_EQ(b.buffers.lightMedia[0], 0);
    VolumeRun r = traceBoth(b, kPaths, 64, 5);
    const uint32_t S = r.device.slotsPerPath;
    std::vector<double> distances;
    size_t escaped = 0;
    for (size_t i = 0; i < r.rays.size(); ++i) {
        escaped += referenceEndCause(r.device.ends[i]) == PCL_END_ESCAPED;
        if (r.device.volumeCounts[i] == 0) continue;
        const PclPhoton& p = r.device.volumeSlots[i * S];
        ASSERT_EQ(bounceOf(p), 0u);
        distances.push_back(length(positionOf(p)));
    }
    std::sort(distances.begin(), distances.end());
    const double N = double(distances.size());
    const double norm = 1.0 - std::exp(-sigmaT * R);
    double D = 0.0;
    for (size_t k = 0; k < distances.size(); ++k) {
        const double F = (1.0 - std::exp(-sigmaT * distances[k])) / norm;
        D = std::max({D, std::fabs(F - k / N), std::fabs(F - (k + 1) / N)});
    }
    // Kolmogorov–Smirnov at α = 0.001: √N D < 1.95.
    std::printf("%zu first scatterings, %zu paths escaped; KS √N D = %.3f (critical 1.95); scattered fraction %.4f "
                "expected %.4f\n",
                distances.size(), escaped, std::sqrt(N) * D, N / double(r.rays.size()), norm);
    EXPECT_LT(std::sqrt(N) * D, 1.95);
    // The fraction that scatters before the boundary: 1 − e^{−σt R} (binomial, 4 σ).
    const double se = std::sqrt(norm * (1.0 - norm) / double(r.rays.size()));
    EXPECT_NEAR(N / double(r.rays.size()), norm, 4.0 * se);
    EXPECT_GT(escaped, 0u);
    EXPECT_LE(divergentFraction(r, b.buffers.sceneRadius), 0.001);
}

// Mean cosine between the directions into and out of each event (from consecutive event
// positions of a path; the first comes from the light at the origin).
TEST(VolumePhotons, ScatteringAnglesHaveMeanCosineG) {
    for (float g : {0.7f, -0.5f, 0.0f}) {
        Medium m;
        m.name = "hg";
        m.sigmaS = Vec3(0.9f);
        m.sigmaA = Vec3(0.1f);
        m.g = g;
        test::BuiltScene b = pointInMedium(m, 0.0f, true);
        VolumeRun r = traceBoth(b, kPaths / 2, 64, 77);
        const uint32_t S = r.device.slotsPerPath;
        double s = 0.0, s2 = 0.0;
        size_t n = 0;
        for (size_t i = 0; i < r.rays.size(); ++i) {
            const uint32_t c = r.device.volumeCounts[i];
            for (uint32_t k = 0; k + 1 < c; ++k) {
                const Vec3 x = positionOf(r.device.volumeSlots[i * S + k]);
                const Vec3 prev = k == 0 ? Vec3(0.0f) : positionOf(r.device.volumeSlots[i * S + k - 1]);
                const Vec3 next = positionOf(r.device.volumeSlots[i * S + k + 1]);
                if (!(length(x - prev) > 0.0f) || !(length(next - x) > 0.0f)) continue;  // a flight of length 0 (u = 0)
                const double mu = dot(normalize(x - prev), normalize(next - x));
                s += mu;
                s2 += mu * mu;
                ++n;
            }
        }
        const double mean = s / double(n), se = std::sqrt((s2 / double(n) - mean * mean) / double(n));
        std::printf("g %.2f: mean cosine %.5f over %zu events (se %.5f)\n", g, mean, n, se);
        EXPECT_NEAR(mean, g, 4.0 * se) << "g " << g;
        EXPECT_LE(divergentFraction(r, b.buffers.sceneRadius), 0.001) << "g " << g;
    }
}

// The shipped media scenes: the device's volume photons (and surface ones) equal the twin's.
TEST(VolumePhotons, DeviceEqualsTwinOnTheShippedMediaScenes) {
    for (const char* name : {"cornell-fog", "hazy-room"}) {
        test::BuiltScene b =
            test::build(loadScene(std::string(PHOTONCL_SOURCE_DIR) + "/scenes/media/" + name + ".json"));
        ASSERT_TRUE(b.buffers.hasMedia);
        VolumeRun r = traceBoth(b, 20000, 16, 3);
        size_t volume = 0;
        for (uint32_t c : r.twin.volumeCounts) volume += c;
        std::printf("%s: %zu volume photons\n", name, volume);
        EXPECT_GT(volume, 0u);
        EXPECT_LE(divergentFraction(r, b.buffers.sceneRadius), 0.001) << name;
    }
}

// A directional light in a global medium: its light crosses infinitely much fog (the reference
// path tracer's shadow rays find no light either), so every path ends at once with no record;
// the same light with the fog only inside a sphere sends photons in.
TEST(VolumePhotons, DirectionalLightInAGlobalMediumSendsNothing) {
    Medium m;
    m.name = "fog";
    m.sigmaS = Vec3(0.5f);
    m.sigmaA = Vec3(0.1f);
    for (bool global : {true, false}) {
        Scene s = pointInMedium(m, 1.0f, global).scene;
        Light sun;
        sun.type = LightType::Directional;
        sun.direction = Vec3(0.0f, -1.0f, 0.0f);
        sun.irradiance = Vec3(1.0f);
        s.lights = {sun};
        test::BuiltScene b = test::build(s);
        ASSERT_EQ(b.buffers.lightMedia.size(), 1u);
        EXPECT_EQ(b.buffers.lightMedia[0], global ? PCL_MEDIUM_UNREACHABLE : PCL_NO_MEDIUM);
        VolumeRun r = traceBoth(b, 2000, 16, 1);
        size_t records = 0, immediate = 0;
        for (size_t i = 0; i < r.rays.size(); ++i) {
            records += r.device.counts[i] + r.device.volumeCounts[i];
            immediate += r.device.ends[i] == (1u | PCL_END_ABSORBED << 8);
        }
        std::printf("%s: %zu records, %zu of %zu paths ended at once\n", global ? "global fog" : "fog ball", records,
                    immediate, r.rays.size());
        if (global) {
            EXPECT_EQ(records, 0u);
            EXPECT_EQ(immediate, r.rays.size());
        } else {
            EXPECT_GT(records, 0u);
        }
        EXPECT_EQ(divergentFraction(r, b.buffers.sceneRadius), 0.0);
    }
}

// The photon pass on the fog Cornell box with its glass ball: the volume caustic map holds only
// L S+ V photons (after a specular bounce and nothing else), the volume map every scattering
// event, and neither surface map a volume photon.
TEST(VolumePhotons, VolumeCausticMapHoldsOnlyLSPlusVAndTheSurfaceMapsNoVolumePhotons) {
    test::ScenePhotonPass r =
        test::runScenePhotonPass(std::string(PHOTONCL_SOURCE_DIR) + "/scenes/media/cornell-fog.json", 20000, 4);
    const PhotonMaps& m = r.maps;
    std::printf("global %zu, caustic %zu, volume %zu, volume caustic %zu records\n", m.global.size(), m.caustic.size(),
                m.volume.size(), m.volumeCaustic.size());
    ASSERT_GT(m.volume.size(), 0u);
    ASSERT_GT(m.volumeCaustic.size(), 0u);
    EXPECT_EQ(m.stats.global.volumeDeposits, m.volume.size());
    EXPECT_EQ(m.stats.caustic.volumeDeposits, m.volumeCaustic.size());
    for (const PclPhoton& p : m.volumeCaustic) {
        ASSERT_EQ(p.packed &
                      (PCL_PHOTON_VOLUME | PCL_PHOTON_CAUSTIC | PCL_PHOTON_AFTER_SPECULAR | PCL_PHOTON_AFTER_DIFFUSE),
                  PCL_PHOTON_VOLUME | PCL_PHOTON_CAUSTIC | PCL_PHOTON_AFTER_SPECULAR);
        ASSERT_GE(bounceOf(p), 1u);
        ASSERT_EQ(p.normal, 0u);
    }
    size_t afterVolume = 0;
    for (const PclPhoton& p : m.volume) {
        ASSERT_EQ(p.packed & (PCL_PHOTON_VOLUME | PCL_PHOTON_CAUSTIC), PCL_PHOTON_VOLUME);
        afterVolume += (p.packed & PCL_PHOTON_AFTER_DIFFUSE) != 0;
    }
    EXPECT_GT(afterVolume, 0u);  // multiple scattering reaches the map
    for (const std::vector<PclPhoton>* map : {&m.global, &m.caustic})
        for (const PclPhoton& p : *map) ASSERT_EQ(p.packed & PCL_PHOTON_VOLUME, 0u);
}

}  // namespace
}  // namespace pcl
