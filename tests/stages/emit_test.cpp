// emit_photons (kernels/emit.cl) on its own: properties that need no twin. Total emitted flux
// equals Σ Φ of the lights (1e-4 relative), each light emits its allocation, directions lie in
// the spot cone / the emitting hemisphere / the sphere, origins on the light, sampled densities
// match their analytic moments within 5 standard errors, and batches do not change a photon.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "check/on_device.h"
#include "device_fixture.h"
#include "photon_test_scenes.h"
#include "pipeline/emit.h"
#include "prep/photon_allocation.h"
#include "shared/sampling.h"

namespace pcl {
namespace {

constexpr uint32_t kPhotons = 100000;

// Point, spot and two triangle lights inside a closed box, plus a directional light.
test::BuiltScene lightsScene(bool withDirectional) {
    Scene s;
    int white = test::addMaterial(s, Vec3(0.5f));
    s.meshes.push_back(test::closedBox(1.0f, white));
    s.lights.push_back(test::pointLight(Vec3(0.2f, 0.1f, -0.3f), Vec3(1.0f, 2.0f, 3.0f)));
    s.lights.push_back(test::spotLight(Vec3(0.0f, 0.5f, 0.0f), Vec3(0.3f, -1.0f, 0.2f), Vec3(5.0f, 4.0f, 3.0f),
                                       std::cos(0.3f), std::cos(0.6f)));
    test::addAreaLight(s, 0.99f, 0.25f, Vec3(4.0f, 4.0f, 2.0f));
    if (withDirectional) {
        Light d;
        d.type = LightType::Directional;
        d.direction = normalize(Vec3(0.2f, -1.0f, 0.1f));
        d.irradiance = Vec3(0.3f, 0.2f, 0.1f);
        s.lights.push_back(d);
    }
    return test::build(s);
}

std::vector<PclPhotonRay> emit(const test::BuiltScene& b, uint32_t passKind, uint32_t photons,
                               std::vector<uint32_t>* firstOut = nullptr, uint64_t seed = 7) {
    std::vector<uint32_t> first = lightFirstPhoton(b.buffers, photons, passKind);
    PclPhotonParams p = makePhotonParams(b.geometry, b.buffers, passKind, seed, 64, 0, first.back());
    if (firstOut) *firstOut = first;
    return emitOnDevice(test::testDevice(), b.geometry, b.buffers, first, p);
}

Vec3 dir(const PclPhotonRay& r) { return Vec3(r.dx, r.dy, r.dz); }
Vec3 origin(const PclPhotonRay& r) { return Vec3(r.ox, r.oy, r.oz); }

TEST(Emit, TotalFluxEqualsLightPowersAndEachLightEmitsItsAllocation) {
    test::BuiltScene b = lightsScene(true);
    ASSERT_EQ(b.buffers.lights.size(), 5u);
    std::vector<uint32_t> first;
    std::vector<PclPhotonRay> rays = emit(b, PCL_PASS_GLOBAL, kPhotons, &first);
    ASSERT_EQ(rays.size(), kPhotons);
    double want[3] = {0, 0, 0}, got[3] = {0, 0, 0};
    for (const PclLight& l : b.buffers.lights)
        for (int c = 0; c < 3; ++c) want[c] += l.power[c];
    std::vector<uint32_t> perLight(b.buffers.lights.size(), 0);
    for (size_t i = 0; i < rays.size(); ++i) {
        for (int c = 0; c < 3; ++c) got[c] += rays[i].power[c];
        ASSERT_LT(rays[i].light, perLight.size());
        ++perLight[rays[i].light];
        // Photons are handed out light by light in index order.
        EXPECT_GE(i, first[rays[i].light]);
        EXPECT_LT(i, first[rays[i].light + 1]);
    }
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-4 * want[c]) << "channel " << c;
    for (size_t l = 0; l < perLight.size(); ++l) {
        EXPECT_EQ(perLight[l], first[l + 1] - first[l]) << "light " << l;
        EXPECT_GT(perLight[l], 0u);
    }
    // Shares follow scalar power (largest remainder: within one photon).
    double total = 0;
    for (const PclLight& l : b.buffers.lights) total += scalarPower(l);
    for (size_t l = 0; l < perLight.size(); ++l)
        EXPECT_NEAR(perLight[l], kPhotons * scalarPower(b.buffers.lights[l]) / total, 1.0) << "light " << l;
}

TEST(Emit, DirectionsAndOriginsLieOnTheirLights) {
    test::BuiltScene b = lightsScene(true);
    std::vector<PclPhotonRay> rays = emit(b, PCL_PASS_GLOBAL, kPhotons);
    const auto& lights = b.buffers.lights;
    size_t checked[4] = {0, 0, 0, 0};
    double cosSum = 0;  // triangle lights: mean cosθ of a cosine lobe is 2/3
    size_t cosN = 0, insideInner = 0, spotN = 0;
    double sphereMean[3] = {0, 0, 0};
    size_t pointN = 0;
    for (const PclPhotonRay& r : rays) {
        const PclLight& L = lights[r.light];
        Vec3 d = dir(r), o = origin(r);
        Vec3 axis(L.axis[0], L.axis[1], L.axis[2]), p(L.p[0], L.p[1], L.p[2]);
        ASSERT_NEAR(length(d), 1.0f, 1e-5f);
        EXPECT_EQ(r.time, 0.0f);  // no motion in the scene
        ++checked[L.type];
        switch (L.type) {
            case PCL_LIGHT_POINT:
                EXPECT_EQ(o.x, p.x);
                EXPECT_EQ(o.y, p.y);
                EXPECT_EQ(o.z, p.z);
                sphereMean[0] += d.x, sphereMean[1] += d.y, sphereMean[2] += d.z;
                ++pointN;
                break;
            case PCL_LIGHT_SPOT: {
                float c = dot(d, axis);
                EXPECT_GE(c, L.cosOuter - 1e-5f);
                insideInner += c >= L.cosInner;
                ++spotN;
                break;
            }
            case PCL_LIGHT_TRIANGLE: {
                float c = dot(d, axis);
                EXPECT_GE(c, -1e-6f);
                cosSum += c;
                ++cosN;
                // On the triangle, lifted by rayEpsilon along the normal.
                Vec3 e1(L.e1[0], L.e1[1], L.e1[2]), e2(L.e2[0], L.e2[1], L.e2[2]);
                Vec3 q = o - p;
                EXPECT_NEAR(dot(q, axis), b.buffers.rayEpsilon, 1e-5f);
                Vec3 inPlane = q - axis * dot(q, axis);
                // Barycentrics of inPlane in (e1, e2).
                float d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2);
                float q1 = dot(inPlane, e1), q2 = dot(inPlane, e2);
                float det = d11 * d22 - d12 * d12;
                float a1 = (d22 * q1 - d12 * q2) / det, a2 = (d11 * q2 - d12 * q1) / det;
                EXPECT_GE(a1, -1e-5f);
                EXPECT_GE(a2, -1e-5f);
                EXPECT_LE(a1 + a2, 1.0f + 1e-5f);
                break;
            }
            case PCL_LIGHT_DIRECTIONAL: {
                EXPECT_EQ(d.x, axis.x);
                EXPECT_EQ(d.y, axis.y);
                EXPECT_EQ(d.z, axis.z);
                // On the disc of radius R, 2R behind the centre.
                Vec3 q = o - p;
                EXPECT_NEAR(dot(q, axis), -2.0f * L.radius, 1e-4f * L.radius);
                Vec3 inPlane = q - axis * dot(q, axis);
                EXPECT_LE(length(inPlane), L.radius * (1.0f + 1e-5f));
                break;
            }
        }
    }
    for (int t = 0; t < 4; ++t) EXPECT_GT(checked[t], 1000u) << "light type " << t;
    // Uniform sphere: each mean component 0, σ = √(1/3 / n).
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(sphereMean[c] / pointN, 0.0, 5.0 * std::sqrt(1.0 / 3.0 / pointN));
    // Cosine lobe: E[cosθ] = 2/3, Var = 1/2 - 4/9 = 1/18.
    EXPECT_NEAR(cosSum / cosN, 2.0 / 3.0, 5.0 * std::sqrt(1.0 / 18.0 / cosN));
    // Spot: the core holds P_in = w_in / (w_in + w_fall) of the photons.
    const PclLight& spot = lights[1];
    double wIn = 1.0 - spot.cosInner, wFall = (spot.cosInner - spot.cosOuter) / 2.0, pIn = wIn / (wIn + wFall);
    EXPECT_NEAR(double(insideInner) / spotN, pIn, 5.0 * std::sqrt(pIn * (1 - pIn) / spotN));
}

TEST(Emit, SpotFalloffFollowsSmoothstep) {
    // Within the falloff band the density in t = (cosθ - cosOuter)/(cosInner - cosOuter) is
    // 6t² - 4t³ (smoothstep, normalised): check its first two moments.
    Scene s;
    s.lights.push_back(test::spotLight(Vec3(0.0f), Vec3(0, 0, 1), Vec3(1.0f), 0.9f, 0.2f));
    test::BuiltScene b = test::build(s);
    std::vector<PclPhotonRay> rays = emit(b, PCL_PASS_GLOBAL, kPhotons);
    double sum = 0, sum2 = 0;
    size_t n = 0;
    for (const PclPhotonRay& r : rays) {
        if (r.dz >= 0.9f) continue;
        double t = (r.dz - 0.2) / (0.9 - 0.2);
        ASSERT_GE(t, -1e-5);
        sum += t;
        sum2 += t * t;
        ++n;
    }
    // E[t] = ∫ t (6t² - 4t³) dt = 6/4 - 4/5 = 0.7; E[t²] = 6/5 - 4/6 = 8/15.
    double var = 8.0 / 15.0 - 0.49;
    EXPECT_NEAR(sum / n, 0.7, 5.0 * std::sqrt(var / n));
    EXPECT_NEAR(sum2 / n, 8.0 / 15.0, 0.01);
}

// Pearson's chi-square of counts against equal expected counts, and its p-value by the
// Wilson–Hilferty cube-root normal approximation (accurate to ~1e-3 at these degrees of freedom).
double chiSquarePValue(const std::vector<size_t>& counts) {
    size_t n = 0;
    for (size_t c : counts) n += c;
    double expected = double(n) / counts.size(), chi2 = 0;
    for (size_t c : counts) chi2 += (c - expected) * (c - expected) / expected;
    double k = double(counts.size() - 1);
    double z = (std::cbrt(chi2 / k) - (1.0 - 2.0 / (9.0 * k))) / std::sqrt(2.0 / (9.0 * k));
    return 0.5 * std::erfc(z / std::sqrt(2.0));
}

// Each light's warp maps the unit square onto its distribution; mapped back through the
// analytic CDF (an equal-probability 16 × 16 grid), emitted photons must be uniform.
// Chi-square at α = 0.01 over the four light types with Šidák's correction (pbrt-v4 and
// Mitsuba test their warps this way).
TEST(Emit, EveryLightTypePassesChiSquareOnItsEqualProbabilityGrid) {
    test::BuiltScene b = lightsScene(true);
    std::vector<PclPhotonRay> rays = emit(b, PCL_PASS_GLOBAL, 400000, nullptr, 21);
    const int G = 16;
    std::vector<std::vector<size_t>> bins(4, std::vector<size_t>(G * G, 0));
    for (const PclPhotonRay& r : rays) {
        const PclLight& L = b.buffers.lights[r.light];
        PclV3 axis = sampling_v3(L.axis[0], L.axis[1], L.axis[2]), t, bb;
        sampling_basis(axis, &t, &bb);
        PclV3 d = sampling_v3(r.dx, r.dy, r.dz);
        double u = 0, v = 0;  // the two CDF coordinates, each uniform on [0, 1)
        auto azimuth = [&](PclV3 w) {
            double phi = std::atan2(double(sampling_dot(w, bb)), double(sampling_dot(w, t)));
            return (phi < 0 ? phi + 2 * 3.14159265358979323846 : phi) / (2 * 3.14159265358979323846);
        };
        switch (L.type) {
            case PCL_LIGHT_POINT:  // uniform sphere: z uniform on [-1, 1]
                u = (1.0 - d.z) / 2.0;
                v = azimuth(d);
                break;
            case PCL_LIGHT_SPOT: {  // the falloff CDF of kernels/README.md
                double c = sampling_dot(d, axis);
                double wIn = 1.0 - L.cosInner, wFall = (L.cosInner - L.cosOuter) / 2.0, pIn = wIn / (wIn + wFall);
                if (c >= L.cosInner) {
                    u = (1.0 - c) / (wIn + wFall);
                } else {
                    double x = std::max(0.0, (c - L.cosOuter) / (L.cosInner - L.cosOuter));
                    u = pIn + (1.0 - pIn) * (2 * x * x * x - x * x * x * x);
                }
                v = azimuth(d);
                break;
            }
            case PCL_LIGHT_TRIANGLE: {  // cosine lobe: sin²θ uniform
                double c = std::min(1.0, double(sampling_dot(d, axis)));
                u = 1.0 - c * c;
                v = azimuth(d);
                break;
            }
            case PCL_LIGHT_DIRECTIONAL: {  // uniform disc: r² uniform
                PclV3 q = sampling_v3(r.ox - L.p[0], r.oy - L.p[1], r.oz - L.p[2]);
                double x = sampling_dot(q, t) / L.radius, y = sampling_dot(q, bb) / L.radius;
                u = x * x + y * y;
                double phi = std::atan2(y, x);
                v = (phi < 0 ? phi + 2 * 3.14159265358979323846 : phi) / (2 * 3.14159265358979323846);
                break;
            }
        }
        int iu = std::min(G - 1, std::max(0, int(u * G))), iv = std::min(G - 1, std::max(0, int(v * G)));
        ++bins[L.type][iu * G + iv];
    }
    const double alpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / 4.0);  // Šidák over the four tests
    const char* names[4] = {"point", "spot", "triangle", "directional"};
    for (int type = 0; type < 4; ++type) {
        size_t n = 0;
        for (size_t c : bins[type]) n += c;
        ASSERT_GT(n, size_t(G * G * 20)) << names[type] << ": too few photons for the test";
        double p = chiSquarePValue(bins[type]);
        std::printf("%s light: %zu photons, chi-square p = %.4f\n", names[type], n, p);
        EXPECT_GT(p, alpha) << names[type];
    }
}

TEST(Emit, BatchesEmitTheSamePhotonsAsOneLaunch) {
    test::BuiltScene b = lightsScene(true);
    std::vector<uint32_t> first = lightFirstPhoton(b.buffers, 10000, PCL_PASS_GLOBAL);
    std::vector<PclPhotonRay> whole = emit(b, PCL_PASS_GLOBAL, 10000);
    std::vector<PclPhotonRay> pieces;
    for (uint32_t f = 0; f < 10000; f += 3333) {
        uint32_t n = std::min<uint32_t>(3333, 10000 - f);
        PclPhotonParams p = makePhotonParams(b.geometry, b.buffers, PCL_PASS_GLOBAL, 7, 64, f, n);
        auto part = emitOnDevice(test::testDevice(), b.geometry, b.buffers, first, p);
        pieces.insert(pieces.end(), part.begin(), part.end());
    }
    ASSERT_EQ(pieces.size(), whole.size());
    EXPECT_EQ(std::memcmp(pieces.data(), whole.data(), whole.size() * sizeof(PclPhotonRay)), 0);
    // Another seed gives other photons.
    std::vector<PclPhotonRay> other = emit(b, PCL_PASS_GLOBAL, 10000, nullptr, 8);
    EXPECT_NE(std::memcmp(other.data(), whole.data(), whole.size() * sizeof(PclPhotonRay)), 0);
}

TEST(Emit, CausticPassEmitsOnlyIntoMarkedCellsWithScaledFlux) {
    Scene s;
    s.lights.push_back(test::pointLight(Vec3(0.0f), Vec3(2.0f)));
    s.lights.push_back(test::spotLight(Vec3(0.0f), Vec3(0, 0, 1), Vec3(3.0f), 0.8f, 0.5f));
    test::BuiltScene b = test::build(s);
    // Point light: only cells with cy >= 16 (s2 ≥ 1/2: φ in [π, 2π), so d.y ≤ 0); spot: none.
    b.buffers.projCells.clear();
    for (uint32_t k = 16 * PCL_PROJ_GRID; k < PCL_PROJ_GRID * PCL_PROJ_GRID; ++k) b.buffers.projCells.push_back(k);
    b.buffers.lights[0].projFirst = 0;
    b.buffers.lights[0].projCount = static_cast<uint32_t>(b.buffers.projCells.size());
    std::vector<uint32_t> first;
    std::vector<PclPhotonRay> rays = emit(b, PCL_PASS_CAUSTIC, kPhotons, &first);
    ASSERT_EQ(first[1], kPhotons);
    ASSERT_EQ(first[2], kPhotons);  // the spot light has no marked cell: no caustic photons
    double flux = 0;
    for (const PclPhotonRay& r : rays) {
        ASSERT_EQ(r.light, 0u);
        EXPECT_LE(r.dy, 1e-6f);
        flux += r.power[0];
    }
    EXPECT_NEAR(flux, b.buffers.lights[0].power[0] * 0.5, 1e-4 * flux);

    // Every cell marked: the caustic pass carries the full power, directions everywhere.
    test::markAllProjectionCells(b.buffers);
    rays = emit(b, PCL_PASS_CAUSTIC, kPhotons, &first);
    double total = 0, want = b.buffers.lights[0].power[0] + b.buffers.lights[1].power[0];
    size_t up = 0;
    for (const PclPhotonRay& r : rays) total += r.power[0], up += r.dy > 0.0f;
    EXPECT_NEAR(total, want, 1e-4 * want);
    EXPECT_GT(up, kPhotons / 4);
}

TEST(Emit, MovingScenesSampleTimeAndMoveTriangleLights) {
    Scene s;
    test::addAreaLight(s, 0.0f, 0.5f, Vec3(1.0f));
    s.meshes.back().motion = Vec3(1.0f, 0.0f, 0.0f);
    test::BuiltScene b = test::build(s);
    ASSERT_TRUE(b.buffers.hasMotion);
    std::vector<PclPhotonRay> rays = emit(b, PCL_PASS_GLOBAL, 20000);
    double mean = 0;
    for (const PclPhotonRay& r : rays) {
        ASSERT_GE(r.time, 0.0f);
        ASSERT_LT(r.time, 1.0f);
        mean += r.time;
        // The quad spans x in [-0.5, 0.5] at time 0 and moves by +1 over the shutter.
        EXPECT_GE(r.ox, -0.5f + r.time - 1e-5f);
        EXPECT_LE(r.ox, 0.5f + r.time + 1e-5f);
    }
    EXPECT_NEAR(mean / rays.size(), 0.5, 5.0 * std::sqrt(1.0 / 12.0 / rays.size()));
}

}  // namespace
}  // namespace pcl
