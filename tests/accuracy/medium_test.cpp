// The reference path tracer in participating media against closed forms:
//  * transmittance through a slab and a sphere: exp(−σt d), queried directly and rendered;
//  * single scattering of a point light in an infinite medium, per pixel, against the airlight
//    integral (Sun et al. 2005) evaluated by quadrature in the test;
//  * a non-absorbing medium inside the white furnace (a glowing closed box of albedo ρ): the
//    radiance stays Le/(1−ρ) everywhere, with and without light sampling (the MIS weights at
//    medium vertices), also through a glass ball of milk and a smoke cube with no surface;
//  * the same bits for any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <vector>

#include "accuracy/pixel_stats.h"
#include "common/test_scenes.h"
#include "core/math.h"
#include "geometry/scene_geometry.h"
#include "image/film.h"
#include "reference/camera.h"
#include "reference/path_tracer.h"
#include "reference/sampler.h"
#include "reference/sampling.h"

using namespace pcl;
using test_scenes::addBoundaryMaterial;
using test_scenes::addBox;
using test_scenes::addEmitter;
using test_scenes::addGlass;
using test_scenes::addMaterial;
using test_scenes::addMedium;
using test_scenes::addMediumSphere;

namespace {

void setCamera(Scene& scene, Vec3 pos, Vec3 at, float vfov, int w, int h) {
    test_scenes::setCamera(scene, pos, at, Vec3(0, 1, 0), vfov, w, h);
}

// Adaptive Simpson quadrature of f over [a, b] to absolute tolerance eps.
double adaptiveSimpson(const std::function<double(double)>& f, double a, double b, double eps, double fa, double fm,
                       double fb, double whole, int depth) {
    const double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
    const double flm = f(lm), frm = f(rm);
    const double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm), right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    if (depth <= 0 || std::abs(left + right - whole) <= 15.0 * eps) return left + right + (left + right - whole) / 15.0;
    return adaptiveSimpson(f, a, m, eps / 2, fa, flm, fm, left, depth - 1) +
           adaptiveSimpson(f, m, b, eps / 2, fm, frm, fb, right, depth - 1);
}
double integrate(const std::function<double(double)>& f, double a, double b, double eps) {
    const double fa = f(a), fb = f(b), fm = f(0.5 * (a + b));
    return adaptiveSimpson(f, a, b, eps, fa, fm, fb, (b - a) / 6.0 * (fa + 4.0 * fm + fb), 40);
}

// Single scattering of a point light (intensity I, at q) seen along the ray o + t d (d unit) in
// an infinite homogeneous medium, one channel (Sun et al. 2005, the airlight integral):
//   L = ∫_0^∞ σs p(μ(t)) I e^{−σt t} e^{−σt r(t)} / r(t)² dt,   r(t) = |q − o − t d|.
// With t = t0 + h tan θ (t0 the closest approach, h its distance) dt / r² = dθ / h and the
// integrand is smooth in θ ∈ (atan(−t0/h), π/2).
double airlight(Vec3 o, Vec3 d, Vec3 q, double I, double sigmaS, double sigmaT, double g) {
    const Vec3 oq = q - o;
    const double t0 = dot(oq, d);
    const double h = std::sqrt(std::max(1e-12, double(dot(oq, oq)) - t0 * t0));
    auto hg = [g](double mu) { return (1.0 - g * g) / (4.0 * kPiD * std::pow(1.0 + g * g - 2.0 * g * mu, 1.5)); };
    auto f = [&](double theta) {
        if (theta >= 0.5 * kPiD) return 0.0;
        const double t = t0 + h * std::tan(theta), r = h / std::cos(theta);
        const double mu = -std::sin(theta);  // cosine between d and the direction toward q
        return sigmaS * hg(mu) * I * std::exp(-sigmaT * (t + r)) / h;
    };
    return integrate(f, std::atan2(-t0, h), 0.5 * kPiD, 1e-10);
}

}  // namespace

// exp(−σt d) along segments through an invisible-boundary slab, a sphere and the fog around
// them, to float precision; 0 through an opaque quad or a dielectric (shadow rays do not
// refract).
TEST(MediumAccuracy, TransmittanceThroughSlabAndSphere) {
    Scene scene;
    const int boundary = addBoundaryMaterial(scene);
    const Vec3 slabSigmaA(0.5f, 1.0f, 2.0f), slabSigmaS(0.3f, 0.0f, 0.1f);
    const int slab = addMedium(scene, slabSigmaA, slabSigmaS, 0.4f);
    const int milk = addMedium(scene, Vec3(0.1f), Vec3(3.0f, 4.0f, 5.0f), 0.8f);
    const int fog = addMedium(scene, Vec3(0.01f), Vec3(0.05f, 0.1f, 0.2f), 0.0f);
    addBox(scene, Vec3(-5, -5, 0.0f), Vec3(5, 5, 0.8f), boundary, slab);  // 0.8 m thick along z
    addMediumSphere(scene, Vec3(20, 0, 0), 0.5f, boundary, milk);
    const int glass = addGlass(scene, 1.5f);
    addMediumSphere(scene, Vec3(-20, 0, 0), 0.5f, glass, -1);
    addBox(scene, Vec3(40, -1, -1), Vec3(41, 1, 1), addMaterial(scene, Vec3(0.5f)), -1);
    scene.camera.position = Vec3(0, 0, 10);
    scene.camera.lookAt = Vec3(0, 0, 0);
    SceneGeometry geometry = SceneGeometry::build(scene);
    PathTracer tracer(scene, geometry, PathTracerSettings{});

    auto expectTr = [](Vec3 got, Vec3 expected, const char* what) {
        for (int c = 0; c < 3; ++c) {
            std::printf("%s channel %d: %.7f expected %.7f\n", what, c, got[c], expected[c]);
            EXPECT_NEAR(got[c], expected[c], 2e-6 + 1e-5 * expected[c]) << what << " channel " << c;
        }
    };
    auto expTr = [](Vec3 sigmaT, float d) {
        return Vec3(std::exp(-sigmaT.x * d), std::exp(-sigmaT.y * d), std::exp(-sigmaT.z * d));
    };
    // Straight through the slab, oblique (path length 0.8 / cos 30°), from inside it to outside.
    expectTr(tracer.transmittance(Vec3(1, 2, -1), Vec3(1, 2, 2), 0.0f), expTr(slabSigmaA + slabSigmaS, 0.8f), "slab");
    const float c30 = std::cos(kPi / 6);
    expectTr(tracer.transmittance(Vec3(0, 0, -1), Vec3(0, 3.0f * std::tan(kPi / 6), 2), 0.0f),
             expTr(slabSigmaA + slabSigmaS, 0.8f / c30), "slab at 30 degrees");
    expectTr(tracer.transmittance(Vec3(0, 0, 0.3f), Vec3(0, 0, 3), 0.0f), expTr(slabSigmaA + slabSigmaS, 0.5f),
             "from inside the slab");
    // Through the milk sphere's centre: 2r of milk.
    expectTr(tracer.transmittance(Vec3(20, 0, -3), Vec3(20, 0, -1), 0.0f), Vec3(1.0f), "beside the sphere");
    expectTr(tracer.transmittance(Vec3(17, 0, -3), Vec3(23, 0, -3), 0.0f), Vec3(1.0f), "vacuum");
    expectTr(tracer.transmittance(Vec3(18, 0, 0), Vec3(22, 0, 0), 0.0f),
             expTr(scene.media[size_t(milk)].sigmaT(), 1.0f), "sphere");
    // Blocked: the dielectric ball and the opaque box.
    expectTr(tracer.transmittance(Vec3(-22, 0, 0), Vec3(-18, 0, 0), 0.0f), Vec3(0.0f), "through glass");
    expectTr(tracer.transmittance(Vec3(39, 0, 0), Vec3(42, 0, 0), 0.0f), Vec3(0.0f), "through an opaque box");

    // Fog everywhere else: 3 m of fog and 0.8 m of slab.
    scene.globalMedium = fog;
    PathTracer foggy(scene, geometry, PathTracerSettings{});
    const Vec3 both = expTr(scene.media[size_t(fog)].sigmaT(), 3.0f) * expTr(slabSigmaA + slabSigmaS, 0.8f);
    expectTr(foggy.transmittance(Vec3(1, 2, -1.5f), Vec3(1, 2, 2.3f), 0.0f), both, "fog and slab");
}

// An emitting quad seen through the absorbing slab: every pixel's expected radiance is
// Le exp(−σa d) per channel. Rendered, so this checks free-flight sampling with its weights
// (σ differs per channel: the channel choice and the averaged density), and the camera ray's
// crossings of invisible boundaries.
TEST(MediumAccuracy, RenderedSlabTransmittance) {
    Scene scene;
    const int boundary = addBoundaryMaterial(scene);
    const Vec3 sigmaA(0.5f, 1.0f, 2.0f);
    addBox(scene, Vec3(-5, -5, 0.0f), Vec3(5, 5, 0.8f), boundary, addMedium(scene, sigmaA, Vec3(0.0f), 0.0f));
    const Vec3 Le(1.0f, 2.0f, 3.0f);
    const int lamp = addEmitter(scene, Vec3(0.0f), Le);
    TriangleMesh quad;  // facing +z, toward the camera
    quad.positions = {{-4, -4, -1}, {4, -4, -1}, {4, 4, -1}, {-4, 4, -1}};
    quad.indices = {0, 1, 2, 0, 2, 3};
    quad.material = lamp;
    scene.meshes.push_back(quad);
    setCamera(scene, Vec3(0, 0, 3), Vec3(0, 0, 0), 10.0f, 8, 8);  // every ray nearly along −z
    PathTracerSettings settings;
    settings.samplesPerPixel = testSpp(512);
    settings.seed = testSeed(3);
    const PixelStats px = renderWithErrors(scene, settings);
    for (int c = 0; c < 3; ++c) {
        double mean = 0.0, expected = 0.0, se2 = 0.0;
        for (size_t i = 0; i < px.mean.size(); ++i) {
            // The ray's path length in the slab: 0.8 / cos of its angle to the axis (≤ 5° off).
            RayCamera camera(scene.camera);
            CameraSample cs;
            PclRay r = camera.generateRay(int(i % 8), int(i / 8), cs);
            const Vec3 d = normalize(Vec3(r.dx, r.dy, r.dz));
            expected += Le[c] * std::exp(-sigmaA[c] * 0.8 / std::abs(d.z));
            mean += px.mean[i][c];
            se2 += px.stdError[i][c] * px.stdError[i][c];
        }
        const double n = double(px.mean.size());
        mean /= n;
        expected /= n;
        const double se = std::sqrt(se2) / n;
        std::printf("slab channel %d: mean %.5f expected %.5f (standard error %.5f, z %+.2f)\n", c, mean, expected, se,
                    (mean - expected) / se);
        EXPECT_NEAR(mean, expected, 5.0 * se) << "channel " << c;  // se ≈ 0.6-1.2 % of the value
        EXPECT_NEAR(mean / expected, 1.0, 0.05) << "channel " << c;
    }
}

// A point light in an infinite medium (no surfaces within reach), maxDepth 1: every pixel holds
// the single-scattered airlight. Per pixel against the quadrature of the airlight integral
// averaged over a 6×6 grid in the pixel; isotropic and forward (g = 0.6) scattering, σ
// different per channel.
TEST(MediumAccuracy, SingleScatteringFromPointLightMatchesAirlight) {
    for (float g : {0.0f, 0.6f}) {
        double relErr[2] = {0.0, 0.0};  // mean relative standard error: free flight alone, with equiangular
        for (bool equiangular : {false, true}) {
            Scene scene;
            const Vec3 sigmaS(0.5f, 0.3f, 0.8f), sigmaA(0.1f, 0.3f, 0.05f);
            scene.globalMedium = addMedium(scene, sigmaA, sigmaS, g);
            // One black sphere far behind the camera: a scene needs a shape; e^{−σt 1000} is 0.
            addMediumSphere(scene, Vec3(0, 0, 1000), 1.0f, addMaterial(scene, Vec3(0.0f)), -1);
            Light light;
            light.type = LightType::Point;
            light.position = Vec3(1.2f, 0.3f, -2.0f);  // just outside the view: no pixel sees the light
            light.intensity = Vec3(4.0f, 5.0f, 3.0f);
            scene.lights.push_back(light);
            setCamera(scene, Vec3(0, 0, 1), Vec3(0, 0, -2), 40.0f, 12, 12);

            PathTracerSettings settings;
            settings.samplesPerPixel = testSpp(2048);
            settings.maxDepth = 1;  // single scattering
            settings.seed = testSeed(11);
            settings.equiangular = equiangular;
            const PixelStats px = renderWithErrors(scene, settings);

            RayCamera camera(scene.camera);
            double worstZ = 0.0, sumZ2 = 0.0, sumRatio = 0.0;
            int count = 0;
            for (int y = 0; y < 12; ++y)
                for (int x = 0; x < 12; ++x) {
                    Vec3 expected(0.0f);
                    const int n = 6;
                    for (int j = 0; j < n; ++j)
                        for (int i = 0; i < n; ++i) {
                            CameraSample cs;
                            cs.filmX = (i + 0.5f) / n;
                            cs.filmY = (j + 0.5f) / n;
                            const PclRay r = camera.generateRay(x, y, cs);
                            const Vec3 d = normalize(Vec3(r.dx, r.dy, r.dz));
                            for (int c = 0; c < 3; ++c)
                                expected[c] += float(airlight(Vec3(r.ox, r.oy, r.oz), d, light.position,
                                                              light.intensity[c], sigmaS[c], sigmaS[c] + sigmaA[c], g) /
                                                     (n * n));
                        }
                    const size_t p = size_t(y * 12 + x);
                    for (int c = 0; c < 3; ++c) {
                        const double z = (px.mean[p][c] - expected[c]) / px.stdError[p][c];
                        worstZ = std::max(worstZ, std::abs(z));
                        sumZ2 += z * z;
                        sumRatio += px.mean[p][c] / expected[c];
                        relErr[equiangular] += px.stdError[p][c] / expected[c] / 432.0;
                        ++count;
                    }
                }
            std::printf("airlight g %.1f, equiangular %d: %d pixel-channels, worst |z| %.2f, mean z^2 %.3f, mean ratio "
                        "%.4f, mean relative standard error %.4f\n",
                        g, int(equiangular), count, worstZ, sumZ2 / count, sumRatio / count, relErr[equiangular]);
            // 432 values: |z| < 4.5 (P ≈ 3e-3 for all together if Gaussian); mean z² is 1 ± 0.07 (χ²
            // with 432 dof, σ = √(2/432)); the mean ratio within 1 % (per-pixel errors ~1-2 %).
            EXPECT_LT(worstZ, 4.5) << "g " << g;
            EXPECT_NEAR(sumZ2 / count, 1.0, 0.3) << "g " << g;
            EXPECT_NEAR(sumRatio / count, 1.0, 0.01) << "g " << g;
        }
        // Equiangular sampling (MIS with the free flight's light samples) cancels the light's 1/r²:
        // isotropic, the error at the same samples falls to 0.44 of free flight's (measured); with
        // g = 0.6 the phase function, which neither samples, dominates (0.91): never worse.
        EXPECT_LT(relErr[1], (g == 0.0f ? 0.6 : 1.0) * relErr[0]) << "g " << g;
    }
}

// The white furnace with media: a closed box of albedo ρ emitting Le inward everywhere, filled
// with a non-absorbing medium, holding a glass ball (ior 1.33) of non-absorbing milk and a smoke
// cube with no surface. A uniform, isotropic radiance field L = Le/(1−ρ) solves the transport
// equation there (out-scattering σs L equals in-scattering σs ∫ p L), and refraction in and out of
// the ball cancels (radiance scaled by η² inside), so every pixel expects Le/(1−ρ), whether light
// sampling (with MIS at medium vertices) is on or off.
TEST(MediumAccuracy, NonAbsorbingMediaInTheFurnaceStayUniform) {
    const float rho = 0.5f;
    const Vec3 Le(1.0f, 0.5f, 2.0f);
    Scene scene;
    addBox(scene, Vec3(-1), Vec3(1), addEmitter(scene, Vec3(rho), Le), -1, /*inward=*/true);
    scene.globalMedium = addMedium(scene, Vec3(0.0f), Vec3(1.0f, 2.0f, 0.5f), 0.5f);
    addMediumSphere(scene, Vec3(0.3f, 0.1f, -0.4f), 0.35f, addGlass(scene, 1.33f),
                    addMedium(scene, Vec3(0.0f), Vec3(6.0f, 4.0f, 8.0f), 0.8f));
    addBox(scene, Vec3(-0.7f, -0.6f, -0.8f), Vec3(-0.2f, -0.1f, -0.3f), addBoundaryMaterial(scene),
           addMedium(scene, Vec3(0.0f), Vec3(3.0f), -0.4f));
    setCamera(scene, Vec3(0.1f, 0.2f, 0.8f), Vec3(0.0f, -0.1f, -1.0f), 80.0f, 12, 12);
    const Vec3 expected = Le / (1.0f - rho);

    for (bool lightSampling : {true, false}) {
        PathTracerSettings settings;
        settings.samplesPerPixel = testSpp(lightSampling ? 512 : 1024);
        settings.maxDepth = 256;
        settings.seed = testSeed(5);
        settings.lightSampling = lightSampling;
        const PixelStats px = renderWithErrors(scene, settings);
        for (int c = 0; c < 3; ++c) {
            double mean = 0.0, se2 = 0.0, worstZ = 0.0;
            for (size_t i = 0; i < px.mean.size(); ++i) {
                mean += px.mean[i][c];
                se2 += px.stdError[i][c] * px.stdError[i][c];
                worstZ = std::max(worstZ, double(std::abs(px.mean[i][c] - expected[c]) / px.stdError[i][c]));
            }
            const double n = double(px.mean.size());
            mean /= n;
            const double se = std::sqrt(se2) / n;
            std::printf("furnace with media, light sampling %d, channel %d: mean %.5f expected %.5f (se %.5f), worst "
                        "pixel |z| %.2f\n",
                        lightSampling, c, mean, expected[c], se, worstZ);
            // se is 0.3-0.6 % of the value; 144 pixels per channel: |z| < 5.
            EXPECT_NEAR(mean, expected[c], 5.0 * se) << "light sampling " << lightSampling << " channel " << c;
            EXPECT_NEAR(mean / expected[c], 1.0, 0.02) << "light sampling " << lightSampling << " channel " << c;
            EXPECT_LT(worstZ, 5.0) << "light sampling " << lightSampling << " channel " << c;
        }
    }
}

// Same film bits for 1 and 3 threads in a scene with every kind of medium event.
TEST(MediumAccuracy, DeterministicAcrossThreads) {
    Scene scene;
    addBox(scene, Vec3(-1), Vec3(1), addEmitter(scene, Vec3(0.6f), Vec3(1.0f)), -1, /*inward=*/true);
    scene.globalMedium = addMedium(scene, Vec3(0.2f), Vec3(1.0f), 0.3f);
    addMediumSphere(scene, Vec3(0.2f, 0, -0.3f), 0.3f, addGlass(scene, 1.5f),
                    addMedium(scene, Vec3(0.5f), Vec3(4.0f), 0.7f));
    setCamera(scene, Vec3(0, 0, 0.8f), Vec3(0, 0, -1), 70.0f, 20, 20);
    SceneGeometry geometry = SceneGeometry::build(scene);
    PathTracerSettings settings;
    settings.samplesPerPixel = 8;
    settings.threads = 1;
    const Image a = PathTracer(scene, geometry, settings).render().resolve();
    settings.threads = 3;
    const Image b = PathTracer(scene, geometry, settings).render().resolve();
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)), 0);
}
