// The eye pass in participating media (kernels/eye_paths.cl, kernels/direct_light.cl; README,
// "Eye pass: media"), on the device, against its twin and against closed forms:
//  - the device's eye records, medium segments and direct light equal the twin's on the shipped
//    media scenes (≥ 99.9 % of records within 1e-3);
//  - single scattering from an isotropic point light in an infinite homogeneous medium (the
//    camera ray ends at a far black box): per pixel, the mean of the records' emitted sum
//    against the mean over the same rays of ∫ Tr(t) σs p I Tr(d_l)/d_l² dt by quadrature (the
//    1-D integral of Sun et al. 2005, in θ of the equiangular substitution, where it is smooth),
//    within 5 standard errors per pixel and 1 % pooled;
//  - the transmittance exp(−σt d) of an absorbing slab seen against an emissive quad, per sample
//    (the path length d/|d_z| of each ray), and of a fog around a diffuse floor on its direct
//    light (the eye segment's and the shadow ray's), to 1e-4;
//  - a scene whose medium is a vacuum (σ = 0 everywhere, so the media code runs) gives the
//    records and direct light of the same scene without media, bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "check/eye_stages.h"
#include "check/on_device.h"
#include "check/render.h"
#include "core/math.h"
#include "eye_test_scenes.h"
#include "pipeline/camera_rays.h"
#include "pipeline/direct_light.h"
#include "pipeline/eye_paths.h"
#include "reference/direct_light.h"
#include "reference/eye_paths.h"

namespace pcl {
namespace {

// The closed box [lo, hi] as one mesh of outward-facing quads (a medium's boundary).
TriangleMesh outwardBox(Vec3 lo, Vec3 hi, int material, int medium) {
    TriangleMesh m;
    m.material = material;
    m.medium = medium;
    Vec3 c[8];
    for (int i = 0; i < 8; ++i) c[i] = Vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
    test::addQuad(m, c[0], c[2], c[3], c[1]);  // z = lo, normal −z
    test::addQuad(m, c[4], c[5], c[7], c[6]);  // z = hi, normal +z
    test::addQuad(m, c[0], c[1], c[5], c[4]);  // y = lo, normal −y
    test::addQuad(m, c[2], c[6], c[7], c[3]);  // y = hi, normal +y
    test::addQuad(m, c[0], c[4], c[6], c[2]);  // x = lo, normal −x
    test::addQuad(m, c[1], c[3], c[7], c[5]);  // x = hi, normal +x
    return m;
}

void setCamera(Scene& s, Vec3 position, Vec3 at, float vfov, int w, int h) {
    s.camera.position = position;
    s.camera.lookAt = at;
    s.camera.up = Vec3(0.0f, 1.0f, 0.0f);
    s.camera.vfovDegrees = vfov;
    s.camera.width = w;
    s.camera.height = h;
}

int addInterface(Scene& s) {
    Material m;
    m.name = "boundary";
    m.interface = true;
    s.materials.push_back(m);
    return int(s.materials.size()) - 1;
}

struct EyeRun {
    PclEyeParams params;
    std::vector<PclRay> rays;
    std::vector<PclEyeHit> hits;
    EyeVolumeSegments segments;
};

EyeRun deviceRun(const test::BuiltScene& b, uint32_t strata, uint64_t seed) {
    EyeRun r;
    const PclCameraParams cp = cameraParams(b.scene.camera, false, false, seed, strata);
    r.rays = cameraRaysOnDevice(test::testDevice(), cp);
    r.params = test::eyeParamsFor(cp, b);
    r.hits = eyePathsOnDevice(test::testDevice(), b.geometry, b.buffers, r.rays, r.params, &r.segments);
    return r;
}

PclDirectParams directFor(const test::BuiltScene& b, const PclEyeParams& ep) {
    return directParams(ep, b.geometry, b.buffers, buildAreaLightTable(b.buffers, b.geometry.primitiveCount()), 1, 0);
}

void twinMatch(const char* name) {
    const test::BuiltScene b = test::shippedScene(name, 48, 36);
    const EyeRun d = deviceRun(b, 2, eyePassSeed(5, 0));
    ASSERT_GT(d.params.volumeSegments, 0u);
    EyeVolumeSegments tSeg;
    const std::vector<PclEyeHit> t = referenceEyePaths(b.geometry, b.buffers, d.rays, d.params, &tSeg);
    const StageComparison hits = compareEyeHits(d.hits, t, 1e-3, 3);
    const StageComparison seg = compareEyeSegments(d.segments, tSeg, 1e-3, 3);
    size_t segments = 0, truncated = 0;
    double emitted = 0.0;
    for (size_t i = 0; i < d.hits.size(); ++i) {
        segments += d.segments.counts[i];
        truncated += (d.hits[i].flags & PCL_EYE_TRUNCATED) != 0;
        emitted += d.hits[i].emitted[1];
    }
    const PclDirectParams dp = directFor(b, d.params);
    const std::vector<PclRadiance> dDirect = directLightOnDevice(test::testDevice(), b.geometry, b.buffers, d.hits, dp);
    const std::vector<PclRadiance> tDirect = referenceDirectLight(b.geometry, b.buffers, d.hits, dp);
    const StageComparison direct = compareRadiance("direct light", dDirect, tDirect, 1e-3, 3);
    std::printf("[figure] eye media %s 48x36 2x2: records %.4f %%, segments %.4f %% (%zu, %zu truncated records), "
                "direct %.4f %% within 1e-3; max rel %.2e / %.2e / %.2e; mean emitted (g) %.4g\n",
                name, 100.0 * hits.fraction(), 100.0 * seg.fraction(), segments, truncated, 100.0 * direct.fraction(),
                hits.maxRelError, seg.maxRelError, direct.maxRelError, emitted / double(d.hits.size()));
    EXPECT_GE(hits.fraction(), 0.999);
    EXPECT_GE(seg.fraction(), 0.999);
    EXPECT_GE(direct.fraction(), 0.999);
    EXPECT_EQ(hits.nonFinite + seg.nonFinite + direct.nonFinite, 0u);
    EXPECT_GT(segments, d.hits.size() / 2);  // the camera is in the fog
    EXPECT_GT(emitted, 0.0);
}

TEST(EyeMedia, DeviceMatchesTwinCornellFog) { twinMatch("media/cornell-fog.json"); }
TEST(EyeMedia, DeviceMatchesTwinHazyRoom) { twinMatch("media/hazy-room.json"); }

// ∫_0^tEnd e^{−σt t} σs p(μ) I e^{−σt d_l}/d_l² dt along o + t d toward the light c, by the
// substitution t = Δ + D tanθ (d_l = D/cosθ, μ = d·wi = −sinθ, dt/d_l² = dθ/D): the smooth
// integrand σs I/D e^{−σt (t + d_l)} p(−sinθ), composite Simpson in double.
double singleScatterQuadrature(Vec3 o, Vec3 d, Vec3 c, double tEnd, double sigmaT, double sigmaS, double g, double I) {
    const double ocx = c.x - o.x, ocy = c.y - o.y, ocz = c.z - o.z;
    const double delta = ocx * d.x + ocy * d.y + ocz * d.z;
    const double fx = ocx - delta * d.x, fy = ocy - delta * d.y, fz = ocz - delta * d.z;
    const double D = std::sqrt(fx * fx + fy * fy + fz * fz);
    const double a = std::atan2(-delta, D), b = std::atan2(tEnd - delta, D);
    auto f = [&](double th) {
        const double t = delta + D * std::tan(th), dl = D / std::cos(th), mu = -std::sin(th);
        const double phase = (1.0 - g * g) / (4.0 * kPiD * std::pow(1.0 + g * g - 2.0 * g * mu, 1.5));
        return std::exp(-sigmaT * (t + dl)) * phase;
    };
    const int n = 400;  // the integrand is smooth in θ: Simpson's error ~ (π/400)⁴
    const double h = (b - a) / n;
    double sum = f(a) + f(b);
    for (int k = 1; k < n; ++k) sum += f(a + k * h) * (k % 2 ? 4.0 : 2.0);
    return sigmaS * I / D * sum * h / 3.0;
}

// `passes` passes of 16 × 16 samples per pixel on an 8 × 8 image.
void pointLightSingleScattering(float g, Vec3 sigmaS, float sigmaA, uint32_t passes) {
    Scene s;
    setCamera(s, Vec3(0.0f), Vec3(0.0f, 0.0f, -1.0f), 40.0f, 8, 8);
    Medium m;
    m.name = "fog";
    m.sigmaS = sigmaS;
    m.sigmaA = Vec3(sigmaA);
    m.g = g;
    s.media.push_back(m);
    s.globalMedium = 0;
    s.meshes.push_back(test::closedBox(20.0f, test::addMaterial(s, Vec3(0.0f))));  // far and black
    const Vec3 light(0.3f, 0.2f, -2.0f), I(1.0f);
    s.lights.push_back(test::pointLight(light, I));
    const test::BuiltScene b = test::build(s);
    std::vector<EyeRun> runs;
    for (uint32_t p = 0; p < passes; ++p) runs.push_back(deviceRun(b, 16, eyePassSeed(11, p)));
    const size_t spp = 256, pixels = 64, n = spp * passes;
    double pooledE[3] = {0, 0, 0}, pooledQ[3] = {0, 0, 0}, pooledVar[3] = {0, 0, 0};
    double worstZ = 0.0;
    for (size_t px = 0; px < pixels; ++px) {
        double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0}, q[3] = {0, 0, 0};
        for (const EyeRun& r : runs)
            for (size_t k = 0; k < spp; ++k) {
                const size_t i = px * spp + k;
                const PclRay& ray = r.rays[i];
                PclHit hit;
                ASSERT_TRUE(b.geometry.intersect(ray, hit));
                ASSERT_EQ(r.hits[i].flags, 0u);  // black box: no record, only the light collected on the way
                const Vec3 o(ray.ox, ray.oy, ray.oz), d(ray.dx, ray.dy, ray.dz);
                for (int c = 0; c < 3; ++c) {
                    const double Q =
                        singleScatterQuadrature(o, d, light, hit.t, double(m.sigmaS[c]) + sigmaA, m.sigmaS[c], g, I[c]);
                    const double diff = double(r.hits[i].emitted[c]) - Q;
                    sum[c] += diff;
                    sum2[c] += diff * diff;
                    q[c] += Q;
                    pooledE[c] += r.hits[i].emitted[c];
                    pooledQ[c] += Q;
                }
            }
        for (int c = 0; c < 3; ++c) {
            const double mean = sum[c] / n, var = (sum2[c] / n - mean * mean) / (n - 1);  // of the mean
            pooledVar[c] += var * double(n) * double(n);
            worstZ = std::max(worstZ, std::fabs(mean) / std::sqrt(std::max(var, 1e-30)));
            EXPECT_LE(std::fabs(mean), 5.0 * std::sqrt(var) + 1e-4 * q[c] / n)
                << "pixel " << px << " channel " << c << ": emitted " << (q[c] / n + mean) << ", quadrature "
                << q[c] / n;
        }
    }
    const double total = double(pixels * n);
    for (int c = 0; c < 3; ++c) {
        const double rel = (pooledE[c] - pooledQ[c]) / pooledQ[c], se = std::sqrt(pooledVar[c]) / pooledQ[c];
        std::printf("[figure] single scattering g %.1f channel %d, %zu samples: mean emitted %.6g, quadrature %.6g, "
                    "rel %+.3e (pooled standard error %.2e); worst pixel |z| %.2f\n",
                    g, c, size_t(total), pooledE[c] / total, pooledQ[c] / total, rel, se, worstZ);
        EXPECT_LE(std::fabs(rel), 0.01);
        EXPECT_LE(std::fabs(rel), 4.0 * se);
    }
}

TEST(EyeMedia, SingleScatteringFromAPointLightMatchesQuadratureIsotropic) {
    pointLightSingleScattering(0.0f, Vec3(0.4f), 0.1f, 4);  // 1024 samples per pixel
}
TEST(EyeMedia, SingleScatteringFromAPointLightMatchesQuadratureForwardChromatic) {
    pointLightSingleScattering(0.6f, Vec3(0.2f, 0.4f, 0.6f), 0.1f, 2);
}

TEST(EyeMedia, AbsorbingSlabTransmitsExpMinusSigmaTDistance) {
    Scene s;
    setCamera(s, Vec3(0.0f), Vec3(0.0f, 0.0f, -1.0f), 20.0f, 8, 8);
    Medium m;
    m.name = "ink";
    m.sigmaA = Vec3(0.4f, 1.0f, 2.5f);  // σs = 0: transmittance only
    s.media.push_back(m);
    s.meshes.push_back(outwardBox(Vec3(-3.0f, -3.0f, -2.0f), Vec3(3.0f, 3.0f, -1.5f), addInterface(s), 0));
    TriangleMesh lamp;  // facing the camera (+z), black: the path ends there
    lamp.material = test::addMaterial(s, Vec3(0.0f));
    s.materials.back().emission = Vec3(1.0f, 2.0f, 3.0f);
    test::addQuad(lamp, Vec3(-4, -4, -3), Vec3(4, -4, -3), Vec3(4, 4, -3), Vec3(-4, 4, -3));
    s.meshes.push_back(lamp);
    const test::BuiltScene b = test::build(s);
    const EyeRun r = deviceRun(b, 2, eyePassSeed(3, 0));
    EXPECT_EQ(r.params.cameraMedium, PCL_NO_MEDIUM);
    // The path goes on past the boundary from p − n_f ε (the photon pass's offset): inside the
    // slab it travels (d − ε)/|d_z|, which the exact exp(−σt d/|d_z|) differs from by at most
    // σt ε/|d_z| relative (asserted too).
    const double eps = b.buffers.rayEpsilon;
    double worst = 0.0, worstExact = 0.0;
    for (size_t i = 0; i < r.hits.size(); ++i) {
        const double dz = std::fabs(r.rays[i].dz);
        EXPECT_EQ(r.segments.counts[i], 0u);  // σs = 0: nothing to record
        for (int c = 0; c < 3; ++c) {
            const double Le = s.materials.back().emission[c], sigma = m.sigmaA[c];
            const double expected = Le * std::exp(-sigma * (0.5 - eps) / dz);
            const double exact = Le * std::exp(-sigma * 0.5 / dz);
            const double rel = std::fabs(r.hits[i].emitted[c] - expected) / expected;
            const double relExact = std::fabs(r.hits[i].emitted[c] - exact) / exact;
            worst = std::max(worst, rel);
            worstExact = std::max(worstExact, relExact);
            EXPECT_LE(rel, 1e-4) << "sample " << i << " channel " << c;
            EXPECT_LE(relExact, 1e-4 + 1.01 * sigma * eps / dz) << "sample " << i << " channel " << c;
        }
    }
    std::printf("[figure] slab exp(-sigma_t d): %zu samples, worst rel error %.2e (%.2e against the exact d, "
                "offset eps %.2e)\n",
                r.hits.size(), worst, worstExact, eps);
}

TEST(EyeMedia, DirectLightInFogCarriesBothTransmittances) {
    Scene s;
    setCamera(s, Vec3(0.0f, 1.0f, 0.0f), Vec3(0.0f, 0.0f, -3.0f), 30.0f, 8, 8);
    Medium m;
    m.name = "absorbing";
    m.sigmaA = Vec3(0.3f, 0.6f, 0.9f);
    s.media.push_back(m);
    s.globalMedium = 0;
    TriangleMesh floor;
    floor.material = test::addMaterial(s, Vec3(0.5f));
    test::addQuad(floor, Vec3(-20, 0, 20), Vec3(20, 0, 20), Vec3(20, 0, -20), Vec3(-20, 0, -20));  // normal +y
    s.meshes.push_back(floor);
    const Vec3 light(0.5f, 1.5f, -3.0f);
    s.lights.push_back(test::pointLight(light, Vec3(2.0f)));
    const test::BuiltScene b = test::build(s);
    const EyeRun r = deviceRun(b, 2, eyePassSeed(4, 0));
    const PclDirectParams dp = directFor(b, r.params);
    const std::vector<PclRadiance> L = directLightOnDevice(test::testDevice(), b.geometry, b.buffers, r.hits, dp);
    size_t records = 0;
    double worst = 0.0;
    for (size_t i = 0; i < r.hits.size(); ++i) {
        const PclEyeHit& h = r.hits[i];
        if (!(h.flags & PCL_EYE_DIFFUSE)) continue;
        ++records;
        // The shadow ray starts at p lifted by rayEpsilon along the normal (+y).
        const Vec3 p(h.x, h.y, h.z), toL = light - p, lifted = p + Vec3(0.0f, b.buffers.rayEpsilon, 0.0f);
        const double tEye = length(p - s.camera.position), dl = length(toL), cosS = toL.y / dl;
        const double dShadow = length(light - lifted);
        const double rad[3] = {L[i].r, L[i].g, L[i].b};
        for (int c = 0; c < 3; ++c) {
            const double T = std::exp(-double(m.sigmaA[c]) * tEye);
            const double expected = T * 0.5 / kPiD * 2.0 * cosS / (dl * dl) * std::exp(-double(m.sigmaA[c]) * dShadow);
            worst = std::max({worst, std::fabs(h.throughput[c] - T) / T, std::fabs(rad[c] - expected) / expected});
            EXPECT_NEAR(h.throughput[c], T, 1e-4 * T) << "sample " << i;
            EXPECT_NEAR(rad[c], expected, 1e-4 * expected) << "sample " << i;
        }
    }
    std::printf("[figure] direct light in absorbing fog: %zu records, worst rel error %.2e\n", records, worst);
    EXPECT_GT(records, r.hits.size() / 2);
}

TEST(EyeMedia, VacuumMediumLeavesRecordsAndDirectLightBitIdentical) {
    Scene plain = loadScene(test::shippedScenePath("cornell-glossy.json"));
    plain.camera.width = 32;
    plain.camera.height = 24;
    Scene vacuum = plain;
    Medium m;
    m.name = "vacuum";  // σ = 0 (the loader refuses it; built here to run the media code on nothing)
    vacuum.media.push_back(m);
    vacuum.globalMedium = 0;
    const test::BuiltScene a = test::build(plain), b = test::build(vacuum);
    ASSERT_FALSE(a.buffers.hasMedia);
    ASSERT_TRUE(b.buffers.hasMedia);
    const EyeRun ra = deviceRun(a, 2, eyePassSeed(9, 0)), rb = deviceRun(b, 2, eyePassSeed(9, 0));
    EXPECT_EQ(ra.params.volumeSegments, 0u);
    EXPECT_GT(rb.params.volumeSegments, 0u);
    const std::vector<PclRadiance> da =
        directLightOnDevice(test::testDevice(), a.geometry, a.buffers, ra.hits, directFor(a, ra.params));
    const std::vector<PclRadiance> db =
        directLightOnDevice(test::testDevice(), b.geometry, b.buffers, ra.hits, directFor(b, rb.params));
    size_t same = 0, sameDirect = 0;
    for (size_t i = 0; i < ra.hits.size(); ++i) {
        same += std::memcmp(&ra.hits[i], &rb.hits[i], sizeof(PclEyeHit)) == 0;
        sameDirect += std::memcmp(&da[i], &db[i], sizeof(PclRadiance)) == 0;
    }
    std::printf("[figure] vacuum medium vs none, cornell-glossy: %zu / %zu records and %zu direct identical\n", same,
                ra.hits.size(), sameDirect);
    EXPECT_EQ(same, ra.hits.size());
    EXPECT_EQ(sameDirect, ra.hits.size());
}

}  // namespace
}  // namespace pcl
