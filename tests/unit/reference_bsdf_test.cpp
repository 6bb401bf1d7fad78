// The pieces of the reference path tracer checked on their own: the mixed BSDF's sample(),
// evalCos() and pdf() agree with each other and with quadrature, and the light sampler's
// densities match what it samples.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "geometry/scene_geometry.h"
#include "reference/bsdf.h"
#include "reference/light_sampling.h"
#include "reference/sampling.h"
#include "shared/rng.h"

using namespace pcl;

namespace {

const Vec3 kN(0.0f, 0.0f, 1.0f);

Vec3 direction(float thetaDeg, float phiDeg) {
    float t = thetaDeg * kPi / 180.0f, p = phiDeg * kPi / 180.0f;
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

// ∫ g(ω) dω over the sphere by the midpoint rule in (cos θ, φ): exact to ~1e-4 for smooth g.
template <class G>
double integrateSphere(G g, int nTheta = 800, int nPhi = 800) {
    double sum = 0.0;
    for (int i = 0; i < nTheta; ++i) {
        double z = -1.0 + 2.0 * (i + 0.5) / nTheta, r = std::sqrt(1.0 - z * z);
        for (int j = 0; j < nPhi; ++j) {
            double phi = 2.0 * kPi * (j + 0.5) / nPhi;
            sum += g(Vec3(static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi)),
                          static_cast<float>(z)));
        }
    }
    return sum * (4.0 * kPi) / (static_cast<double>(nTheta) * nPhi);
}

Material mixed(Vec3 rhoD, Vec3 rhoS, SpecularKind kind, float exponent = 0.0f) {
    Material m;
    m.rhoD = rhoD;
    m.rhoS = rhoS;
    m.specular = kind;
    m.phongExponent = exponent;
    return m;
}

// Monte Carlo mean of sample() weights with Philox numbers: the directional albedo.
Vec3 albedoBySampling(const MixedBsdf& bsdf, Vec3 wo, int n, double* deltaFraction = nullptr) {
    Vec3 sum(0.0f);
    int deltas = 0;
    for (int i = 0; i < n; ++i) {
        PclRng r = rng_start(99, static_cast<uint32_t>(i), 0, PCL_RNG_STREAM_TEST);
        float a = rng_next(&r), b = rng_next(&r), c = rng_next(&r);
        BsdfSample s;
        if (bsdf.sample(wo, a, b, c, s)) {
            sum += s.weight;
            deltas += s.delta;
        }
    }
    if (deltaFraction) *deltaFraction = static_cast<double>(deltas) / n;
    return sum / static_cast<float>(n);
}

}  // namespace

TEST(ReferenceBsdf, PdfIntegratesToOneAndMatchesEvalOverSampling) {
    // Diffuse + glossy: pdf integrates to 1 minus the lobe part below the horizon; the sampled
    // albedo E[f cos / pdf] equals ∫ f cos dω by quadrature.
    for (float thetaO : {0.0f, 30.0f, 60.0f}) {
        MixedBsdf bsdf(mixed(Vec3(0.3f), Vec3(0.6f), SpecularKind::Glossy, 12.0f), kN, kN);
        Vec3 wo = direction(thetaO, 20.0f);
        double pdfIntegral = integrateSphere([&](Vec3 w) { return bsdf.pdf(wo, w); });
        double albedo = integrateSphere([&](Vec3 w) { return bsdf.evalCos(wo, w).x; });
        Vec3 sampled = albedoBySampling(bsdf, wo, 200000);
        EXPECT_LE(pdfIntegral, 1.0 + 1e-3);
        if (thetaO == 0.0f) {
            EXPECT_NEAR(pdfIntegral, 1.0, 2e-3);
            EXPECT_NEAR(albedo, 0.9, 2e-3);  // normalised Phong reflects exactly ρs at normal incidence
        }
        EXPECT_NEAR(sampled.x, albedo, 0.01 * albedo) << "theta_o " << thetaO;
    }
    // Pure diffuse: pdf = cos/π, albedo = ρd exactly and every sample weighs ρd.
    MixedBsdf lambert(mixed(Vec3(0.5f, 0.2f, 0.1f), Vec3(0.0f), SpecularKind::None), kN, kN);
    Vec3 wo = direction(45.0f, 0.0f);
    EXPECT_NEAR(integrateSphere([&](Vec3 w) { return lambert.pdf(wo, w); }), 1.0, 1e-3);
    BsdfSample s;
    ASSERT_TRUE(lambert.sample(wo, 0.3f, 0.7f, 0.2f, s));
    EXPECT_NEAR(s.weight.y, 0.2f, 1e-5);
    EXPECT_FALSE(s.delta);
    // Light arriving from below a reflecting surface is not reflected.
    EXPECT_EQ(lambert.evalCos(wo, direction(120.0f, 0.0f)).x, 0.0f);
}

TEST(ReferenceBsdf, MirrorAndDielectricLobes) {
    // Diffuse + mirror: the mirror lobe is chosen in proportion to luminance, its weight is
    // ρs / P(mirror), so the expected reflectance is ρd + ρs.
    MixedBsdf m(mixed(Vec3(0.2f), Vec3(0.7f), SpecularKind::Mirror), kN, kN);
    Vec3 wo = direction(40.0f, 70.0f);
    double deltas;
    Vec3 a = albedoBySampling(m, wo, 100000, &deltas);
    EXPECT_NEAR(a.x, 0.9, 0.005);
    EXPECT_NEAR(deltas, 0.7 / 0.9, 0.01);
    BsdfSample s;
    ASSERT_TRUE(m.sample(wo, 0.99f, 0.1f, 0.1f, s));
    EXPECT_TRUE(s.delta);
    EXPECT_NEAR(dot(s.wi, direction(40.0f, 250.0f)), 1.0f, 1e-5);  // the mirror direction
    // evalCos holds the non-delta part only: here the diffuse term alone.
    EXPECT_NEAR(m.evalCos(wo, s.wi).x, 0.2f / kPi * std::cos(40.0f * kPi / 180.0f), 1e-5);

    // Glass: reflection with probability F (weight ρs), refraction otherwise (Snell; weight ρs
    // (η_i/η_t)², radiance mode: 1/1.5² entering from outside).
    MixedBsdf glass(mixed(Vec3(0.0f), Vec3(1.0f), SpecularKind::Dielectric), kN, kN);
    EXPECT_FALSE(glass.hasNonDelta());  // no light sampling on clear glass
    Vec3 outside = direction(60.0f, 0.0f);
    float F = fresnelDielectric(std::cos(60.0f * kPi / 180.0f), 1.0f, 1.5f);
    int reflected = 0, n = 20000;
    for (int i = 0; i < n; ++i) {
        ASSERT_TRUE(glass.sample(outside, (i + 0.5f) / n, 0.5f, 0.5f, s));
        EXPECT_FLOAT_EQ(s.weight.x, s.wi.z > 0 ? 1.0f : 1.0f / (1.5f * 1.5f));
        EXPECT_FLOAT_EQ(s.radianceScale, s.weight.x);  // what the path tracer's roulette undoes
        if (s.wi.z > 0) ++reflected;
        else EXPECT_NEAR(std::sqrt(1 - s.wi.z * s.wi.z), std::sin(60.0f * kPi / 180.0f) / 1.5f, 1e-5);  // Snell
    }
    EXPECT_NEAR(static_cast<double>(reflected) / n, F, 1e-3);
    // From inside beyond the critical angle (41.8°): always reflected.
    Vec3 inside = direction(180.0f - 50.0f, 0.0f);
    for (float u : {0.01f, 0.5f, 0.99f}) {
        ASSERT_TRUE(glass.sample(inside, u, 0.5f, 0.5f, s));
        EXPECT_LT(s.wi.z, 0.0f);  // stays inside
    }
    // From inside below it (20°): refracted out with weight 1.5² (a camera inside glass sees the
    // world outside η² brighter).
    ASSERT_TRUE(glass.sample(direction(180.0f - 20.0f, 0.0f), 0.99f, 0.5f, 0.5f, s));
    EXPECT_GT(s.wi.z, 0.0f);
    EXPECT_FLOAT_EQ(s.weight.x, 1.5f * 1.5f);
    EXPECT_FLOAT_EQ(s.radianceScale, 1.5f * 1.5f);
}

TEST(ReferenceLightSampling, DensitiesMatchTheSamples) {
    // One emitting triangle and one emitting sphere, chosen by power (π A Le).
    Scene scene;
    Material lamp;
    lamp.emission = Vec3(2.0f);
    scene.materials.push_back(lamp);
    TriangleMesh tri;
    tri.positions = {{0, 2, 0}, {1, 2, 0}, {0, 2, 1}};  // normal cross((1,0,0), (0,0,1)) = (0,-1,0): faces down
    tri.indices = {0, 1, 2};
    scene.meshes.push_back(tri);
    Sphere sphere;
    sphere.centre = {3, 0, 0};
    sphere.radius = 0.5f;
    scene.spheres.push_back(sphere);
    SceneGeometry geometry = SceneGeometry::build(scene);
    LightSampler lights(scene, geometry);
    ASSERT_EQ(lights.count(), 2u);

    Vec3 p(0.2f, 0.0f, 0.3f);
    int n = 0, fromTriangle = 0;
    double estimate = 0.0;  // E[Li cos / pdf · 1{triangle}]: the triangle's irradiance on a receiver facing up
    for (int i = 0; i < 40000; ++i) {
        PclRng r = rng_start(5, static_cast<uint32_t>(i), 0, PCL_RNG_STREAM_TEST);
        float a = rng_next(&r), b = rng_next(&r), c = rng_next(&r);
        LightSample ls;
        ++n;
        if (!lights.sampleLi(p, 0.0f, a, b, c, ls)) continue;
        uint32_t prim = std::abs(ls.point.y - 2.0f) < 1e-5f ? 0u : 1u;  // the sphere stays within |y| ≤ 0.5
        fromTriangle += prim == 0;
        // Same formula from the point's side; float rounding of cos θ at grazing sphere points.
        EXPECT_NEAR(lights.pdfLi(prim, p, ls.point, ls.normal), ls.pdf, 1e-3f * ls.pdf);
        if (prim == 0) estimate += ls.Li.x * std::max(0.0f, ls.wi.y) / ls.pdf;
    }
    // The triangle's irradiance at p by quadrature over the sphere of directions:
    double exact = integrateSphere(
        [&](Vec3 w) {
            if (w.y <= 0) return 0.0;
            float t = 2.0f / w.y;  // where the direction meets the plane y = 2
            Vec3 q = p + w * t;
            bool inside = q.x >= 0 && q.z >= 0 && q.x + q.z <= 1;
            return inside ? 2.0 * w.y : 0.0;
        },
        1600, 1600);
    std::printf("triangle irradiance: sampled %.5f, quadrature %.5f\n", estimate / n, exact);
    EXPECT_NEAR(estimate / n, exact, 0.01 * exact);
    // Chosen by power: the triangle's area 0.5 against the sphere's π.
    EXPECT_NEAR(static_cast<double>(fromTriangle) / n, 0.5 / (0.5 + kPi), 0.01);
    // The back of a one-sided emitter is dark: seen from above, the triangle gives nothing.
    Vec3 above(0.2f, 3.0f, 0.3f);
    for (int i = 0; i < 100; ++i) {
        LightSample ls;
        if (lights.sampleLi(above, 0.0f, 0.01f, (i + 0.5f) / 100, 0.3f, ls)) FAIL() << "lit from behind";
    }
}
