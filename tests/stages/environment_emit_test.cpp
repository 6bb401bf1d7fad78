// Photons from the environment light ("sky", kernels/emit.cl with shared/environment.h): the
// flux the photons carry against the closed form Φ = π R² ∫ L dω (R the scene's bounding-sphere
// radius), for a constant sky (Φ = 4π² R² L: every photon carries Φ/n, float rounding only,
// 1e-4 relative) and a coloured image sky (its luminance exactly, 1e-4, since the density
// follows it; each channel within 5 standard errors of the photons' mean); the device's photons
// against the CPU twin's (reference/emit.cpp); directions against the map's density (χ²).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "check/on_device.h"
#include "core/math.h"
#include "device_fixture.h"
#include "photon_test_scenes.h"
#include "prep/photon_allocation.h"
#include "prep/projection_map.h"
#include "reference/emit.h"
#include "shared/environment.h"

namespace pcl {
namespace {

constexpr uint32_t kPhotons = 200000;

// A diffuse unit sphere with a point light beside it, under `sky`.
test::BuiltScene skyScene(const Environment& sky) {
    Scene s;
    int white = test::addMaterial(s, Vec3(0.5f));
    Sphere sp;
    sp.centre = Vec3(0.0f);
    sp.radius = 1.0f;
    sp.material = white;
    s.spheres.push_back(sp);
    s.lights.push_back(test::pointLight(Vec3(0.0f, 3.0f, 0.0f), Vec3(1.0f)));
    s.environment = sky;
    return test::build(s);
}

Environment constantSky(Vec3 L) {
    Environment e;
    e.scale = L;
    return e;
}

// 16 × 8 texels of different colours and brightness, one row black, turned 30° about +y.
Environment imageSky() {
    Environment e;
    e.scale = Vec3(2.0f);
    e.image = Image(16, 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x)
            e.image.set(x, y,
                        y == 5 ? Vec3(0.0f) : Vec3(0.1f + 0.05f * x, 0.3f + 0.2f * y, (x + y) % 3 == 0 ? 4.0f : 0.2f));
    e.imagePath = "synthetic";
    e.rotationDegrees = 30.0f;
    return e;
}

// ∫ L dω per channel in double, from the texels the scene holds (the closed form's integral).
void skyIntegral(const Environment& e, double out[3]) {
    out[0] = out[1] = out[2] = 0.0;
    const int W = e.image.rgb.empty() ? 1 : e.image.width, H = e.image.rgb.empty() ? 1 : e.image.height;
    for (int y = 0; y < H; ++y) {
        const double omega = 2.0 * kPiD / W * (std::cos(kPiD * y / H) - std::cos(kPiD * (y + 1) / H));
        for (int x = 0; x < W; ++x) {
            const Vec3 L = e.image.rgb.empty() ? e.scale : e.image.at(x, y) * e.scale;
            for (int c = 0; c < 3; ++c) out[c] += double(L[c]) * omega;
        }
    }
}

struct SkyPhotons {
    std::vector<PclPhotonRay> rays;
    uint32_t skyLight = 0, first = 0, count = 0;
};

SkyPhotons emitSky(const test::BuiltScene& b, uint32_t pass = PCL_PASS_GLOBAL) {
    SkyPhotons r;
    std::vector<uint32_t> first = lightFirstPhoton(b.buffers, kPhotons, pass);
    PclPhotonParams p = makePhotonParams(b.geometry, b.buffers, pass, 11, 64, 0, first.back());
    r.rays = emitOnDevice(test::testDevice(), b.geometry, b.buffers, first, p);
    r.skyLight = uint32_t(b.buffers.lights.size() - 1);
    r.first = first[r.skyLight];
    r.count = first[r.skyLight + 1] - first[r.skyLight];
    return r;
}

TEST(EnvironmentEmit, ConstantSkyFluxIsFourPiSquaredRSquaredL) {
    const Vec3 L(1.0f, 0.5f, 0.25f);
    test::BuiltScene b = skyScene(constantSky(L));
    ASSERT_EQ(b.buffers.lights.back().type, PCL_LIGHT_ENVIRONMENT);
    const double R = b.buffers.sceneRadius;
    SkyPhotons s = emitSky(b);
    ASSERT_GT(s.count, kPhotons / 2);  // shared with the point light by power
    double got[3] = {0, 0, 0};
    for (uint32_t i = s.first; i < s.first + s.count; ++i) {
        ASSERT_EQ(s.rays[i].light, s.skyLight);
        for (int c = 0; c < 3; ++c) got[c] += s.rays[i].power[c];
        // Travelling toward the scene from a disc 2R back: the ray passes within R of the centre.
        const Vec3 o(s.rays[i].ox, s.rays[i].oy, s.rays[i].oz), d(s.rays[i].dx, s.rays[i].dy, s.rays[i].dz);
        EXPECT_NEAR(length(d), 1.0f, 1e-5f);
        const Vec3 toCentre = b.buffers.sceneCentre - o;
        EXPECT_NEAR(dot(toCentre, d), 2.0 * R, 1e-4 * R);
        EXPECT_LE(length(toCentre - d * dot(toCentre, d)), R * (1.0 + 1e-5));
    }
    for (int c = 0; c < 3; ++c) {
        const double want = 4.0 * kPiD * kPiD * R * R * L[c];
        std::printf("[figure] constant sky flux, channel %d: %.6g W emitted, 4 pi^2 R^2 L = %.6g (ratio %.6f)\n", c,
                    got[c], want, got[c] / want);
        EXPECT_NEAR(got[c], want, 1e-4 * want) << "channel " << c;
        EXPECT_NEAR(b.buffers.lights.back().power[c], want, 1e-5 * want) << "channel " << c;
    }
}

TEST(EnvironmentEmit, ImageSkyFluxIsPiRSquaredIntegralOfL) {
    const Environment sky = imageSky();
    test::BuiltScene b = skyScene(sky);
    const double R = b.buffers.sceneRadius;
    double integral[3];
    skyIntegral(sky, integral);
    SkyPhotons s = emitSky(b);
    double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
    for (uint32_t i = s.first; i < s.first + s.count; ++i)
        for (int c = 0; c < 3; ++c) {
            sum[c] += s.rays[i].power[c];
            sum2[c] += double(s.rays[i].power[c]) * s.rays[i].power[c];
        }
    const double n = s.count;
    const auto Y = [](const double c[3]) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; };
    const double luminanceWant = kPiD * R * R * Y(integral);
    std::printf("[figure] image sky flux, luminance: %.6g W emitted, pi R^2 integral Y(L) = %.6g (ratio %.6f)\n",
                Y(sum), luminanceWant, Y(sum) / luminanceWant);
    EXPECT_NEAR(Y(sum), luminanceWant, 1e-4 * luminanceWant);
    for (int c = 0; c < 3; ++c) {
        const double want = kPiD * R * R * integral[c];
        const double mean = sum[c] / n, var = std::max(0.0, sum2[c] / n - mean * mean);
        const double se = std::sqrt(var / n) * n;  // of the sum
        std::printf("[figure] image sky flux, channel %d: %.6g W emitted, pi R^2 integral L = %.6g (ratio %.4f, "
                    "standard error %.2f %%)\n",
                    c, sum[c], want, sum[c] / want, 100.0 * se / want);
        EXPECT_NEAR(sum[c], want, 5.0 * se) << "channel " << c << " (standard error " << se << ")";
        EXPECT_LT(std::abs(sum[c] - want), 0.02 * want) << "channel " << c;
    }
}

// The photons' directions follow the map: counts per texel against n × the texel's share of
// ∫ Y(L) dω, Y the luminance (χ² over texels with ≥ 20 expected, 5σ of the χ² distribution), none from the black row.
TEST(EnvironmentEmit, DirectionsFollowTheMapsDensity) {
    const Environment sky = imageSky();
    test::BuiltScene b = skyScene(sky);
    SkyPhotons s = emitSky(b);
    const PclEnvironment& env = b.buffers.sky.environment;
    const uint32_t W = env.width, H = env.height;
    std::vector<double> counts(W * H, 0.0);
    for (uint32_t i = s.first; i < s.first + s.count; ++i) {
        const PclV3 w = sampling_v3(-s.rays[i].dx, -s.rays[i].dy, -s.rays[i].dz);
        counts[env_texel_of(env, w)] += 1.0;
    }
    double chi2 = 0.0;
    int bins = 0;
    for (uint32_t y = 0; y < H; ++y) {
        const double omega = 2.0 * kPiD / W * (std::cos(kPiD * y / H) - std::cos(kPiD * (y + 1) / H));
        for (uint32_t x = 0; x < W; ++x) {
            const float* t = &b.buffers.sky.data[3 * (y * W + x)];
            const double expected = s.count * (0.2126 * t[0] + 0.7152 * t[1] + 0.0722 * t[2]) * omega / env.integral;
            if (y == 5) {
                EXPECT_EQ(counts[y * W + x], 0.0) << "black texel " << x;
            }
            if (expected < 20.0) continue;
            chi2 += (counts[y * W + x] - expected) * (counts[y * W + x] - expected) / expected;
            ++bins;
        }
    }
    ASSERT_GT(bins, 50);
    const double dof = bins - 1;
    EXPECT_LT(chi2, dof + 5.0 * std::sqrt(2.0 * dof)) << bins << " bins";
}

// Device against twin, photon by photon, in both passes (every projection cell marked).
TEST(EnvironmentEmit, DeviceMatchesTwin) {
    test::BuiltScene b = skyScene(imageSky());
    test::markAllProjectionCells(b.buffers);
    for (uint32_t pass : {uint32_t(PCL_PASS_GLOBAL), uint32_t(PCL_PASS_CAUSTIC)}) {
        std::vector<uint32_t> first = lightFirstPhoton(b.buffers, 20000, pass);
        ASSERT_GT(first.back(), 0u);
        PclPhotonParams p = makePhotonParams(b.geometry, b.buffers, pass, 5, 64, 0, first.back());
        std::vector<PclPhotonRay> dev = emitOnDevice(test::testDevice(), b.geometry, b.buffers, first, p);
        std::vector<PclPhotonRay> twin = emitPhotonsReference(b.buffers, first, p);
        ASSERT_EQ(dev.size(), twin.size());
        size_t far = 0;
        for (size_t i = 0; i < dev.size(); ++i) {
            const PclPhotonRay &a = dev[i], &t = twin[i];
            EXPECT_EQ(a.light, t.light);
            const float dd = std::abs(a.dx - t.dx) + std::abs(a.dy - t.dy) + std::abs(a.dz - t.dz);
            const float dOrigin = std::abs(a.ox - t.ox) + std::abs(a.oy - t.oy) + std::abs(a.oz - t.oz);
            float dp = 0.0f;
            for (int c = 0; c < 3; ++c)
                dp = std::max(dp, std::abs(a.power[c] - t.power[c]) / std::max(std::abs(t.power[c]), 1e-20f));
            // ulps of cos/sin apart (1e-4 relative; the scene is 1 across)
            if (dd > 1e-4f || dOrigin > 1e-4f || dp > 1e-4f) ++far;
        }
        std::printf("[figure] sky emit device vs twin, pass %u: %zu of %zu photons differ by > 1e-4\n", pass, far,
                    dev.size());
        EXPECT_LE(far, dev.size() / 1000) << "pass " << pass;
    }
}

// Caustic photons from the sky are aimed at the ball around the specular objects (emit.cl): a
// glass ball (radius a) and a mirror ball (b) above a wide diffuse floor, under a constant sky L.
// Every caustic photon's ray must pass within the target ball, and the power of those that hit
// each ball is the closed form π a² ∫ L dω = 4π² a² L (a sphere, seen from every direction,
// intercepts πa² of a parallel beam): within 4 standard errors (the hit counts are binomial) and
// 5 % (measured +1.4 % and −0.6 %, standard errors 0.9 % and 1.5 %). Unaimed (the whole scene's disc) would hold the same expectation with ~100× fewer hits.
TEST(EnvironmentEmit, CausticPhotonsAimAtTheSpecularObjects) {
    const Vec3 L(1.0f, 0.5f, 0.25f);
    Scene s;
    const int white = test::addMaterial(s, Vec3(0.5f));
    const int glass = test::addMaterial(s, Vec3(0.0f), Vec3(1.0f), SpecularKind::Dielectric, 0.0f, 1.5f);
    const int mirror = test::addMaterial(s, Vec3(0.0f), Vec3(0.9f), SpecularKind::Mirror);
    TriangleMesh floor;
    floor.material = white;
    test::addQuad(floor, Vec3(-10, -1, -10), Vec3(-10, -1, 10), Vec3(10, -1, 10), Vec3(10, -1, -10));
    s.meshes.push_back(floor);
    const Vec3 centres[2] = {Vec3(1.0f, 0.0f, 0.0f), Vec3(-1.0f, 0.5f, 0.3f)};
    const float radii[2] = {0.3f, 0.2f};
    for (int k = 0; k < 2; ++k) {
        Sphere sp;
        sp.centre = centres[k];
        sp.radius = radii[k];
        sp.material = k == 0 ? glass : mirror;
        s.spheres.push_back(sp);
    }
    s.environment = constantSky(L);
    test::BuiltScene b = test::build(s);
    buildProjectionMaps(b.scene, b.geometry, b.buffers);
    const PclLight& sky = b.buffers.lights.back();
    ASSERT_EQ(sky.type, PCL_LIGHT_ENVIRONMENT);
    const Vec3 target(sky.e1[0], sky.e1[1], sky.e1[2]);
    const float targetRadius = sky.e1[3];
    for (int k = 0; k < 2; ++k) EXPECT_LE(length(centres[k] - target) + radii[k], targetRadius * (1.0f + 1e-6f));
    EXPECT_LT(targetRadius, 0.2f * b.buffers.sceneRadius);  // much smaller than the scene's disc

    SkyPhotons e = emitSky(b, PCL_PASS_CAUSTIC);
    ASSERT_GT(e.count, 0u);
    double hitPower[2][3] = {}, hitPowerSq[2] = {};
    uint32_t hits[2] = {0, 0};
    for (uint32_t i = e.first; i < e.first + e.count; ++i) {
        const PclPhotonRay& r = e.rays[i];
        const Vec3 o(r.ox, r.oy, r.oz), d(r.dx, r.dy, r.dz);
        const Vec3 toTarget = target - o;
        ASSERT_LE(length(toTarget - d * dot(toTarget, d)), targetRadius * (1.0f + 1e-4f)) << "photon " << i;
        for (int k = 0; k < 2; ++k) {
            const Vec3 toBall = centres[k] - o;
            if (length(toBall - d * dot(toBall, d)) > radii[k]) continue;
            ++hits[k];
            for (int c = 0; c < 3; ++c) hitPower[k][c] += r.power[c];
            hitPowerSq[k] += double(r.power[0]) * r.power[0];
        }
    }
    for (int k = 0; k < 2; ++k) {
        const double n = e.count, mean = hitPower[k][0] / n;
        const double se = std::sqrt(std::max(0.0, hitPowerSq[k] / n - mean * mean) / n) * n;
        for (int c = 0; c < 3; ++c) {
            const double want = 4.0 * kPiD * kPiD * double(radii[k]) * radii[k] * L[c];
            std::printf("[figure] sky caustic photons on ball %d (radius %.1f), channel %d: %u hits of %u, power "
                        "%.5f, closed form %.5f (ratio %.4f, se %.2f %%)\n",
                        k, radii[k], c, hits[k], e.count, hitPower[k][c], want, hitPower[k][c] / want,
                        100.0 * se / hitPower[k][0]);
            EXPECT_NEAR(hitPower[k][c], want, std::max(4.0 * se * L[c] / L[0], 1e-4 * want)) << "ball " << k;
            EXPECT_NEAR(hitPower[k][c] / want, 1.0, 0.05) << "ball " << k << " channel " << c;
        }
    }
    // The twin aims the same photons.
    std::vector<uint32_t> first = lightFirstPhoton(b.buffers, kPhotons, PCL_PASS_CAUSTIC);
    const PclPhotonParams p = makePhotonParams(b.geometry, b.buffers, PCL_PASS_CAUSTIC, 11, 64, 0, first.back());
    const std::vector<PclPhotonRay> twin = emitPhotonsReference(b.buffers, first, p);
    ASSERT_EQ(twin.size(), e.rays.size());
    size_t far = 0;
    for (uint32_t i = e.first; i < e.first + e.count; ++i) {
        const PclPhotonRay &a = e.rays[i], &t = twin[i];
        const float dOrigin = std::abs(a.ox - t.ox) + std::abs(a.oy - t.oy) + std::abs(a.oz - t.oz);
        const float dp = std::abs(a.power[0] - t.power[0]) / std::max(std::abs(t.power[0]), 1e-20f);
        far += dOrigin > 1e-4f * b.buffers.sceneRadius || dp > 1e-4f;
    }
    EXPECT_LE(far, e.count / 1000) << far << " of " << e.count << " aimed photons differ from the twin's";
}

}  // namespace
}  // namespace pcl
