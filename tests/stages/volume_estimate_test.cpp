// The volume radiance estimate (kernels/volume_estimate.cl, the beam radiance estimate of Jarosz,
// Zwicker & Jensen 2008) against its twin (reference/volume_estimate) and against closed forms:
// photons of known power density in a box give L = ρ_Φ E[p] ∫ Tr dt along a segment (beam) and
// ρ_Φ E[p] at a point, within stated multiples of the estimator's own standard deviation; the
// skip flags drop exactly the photons they name; the error falls as photons grow and r shrinks;
// nothing is NaN and an empty map gives 0. The check command's comparison on the media scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "check/volume_estimate.h"
#include "core/error.h"
#include "core/math.h"
#include "device_fixture.h"
#include "eye_test_scenes.h"
#include "pipeline/volume_estimate.h"
#include "prep/volume_estimate_settings.h"
#include "reference/knn.h"
#include "reference/volume_estimate.h"
#include "shared/sampling.h"

namespace pcl {
namespace {

// A volume photon at p whose direction of travel is `travel` (stored as w = −travel).
PclPhoton volumePhoton(Vec3 p, Vec3 travel, Vec3 power, uint32_t bounce = 1, uint32_t flags = 0) {
    PclPhoton ph{};
    ph.x = p.x, ph.y = p.y, ph.z = p.z;
    ph.rgbe = photon_rgbe_encode(power.x, power.y, power.z);
    ph.packed = photon_dir_encode(-travel.x, -travel.y, -travel.z) | (bounce << PCL_PHOTON_BOUNCE_SHIFT) | flags |
                PCL_PHOTON_VOLUME;
    ph.normal = 0;
    return ph;
}

Vec3 decodedPower(const PclPhoton& p) {
    float r, g, b;
    photon_rgbe_decode(p.rgbe, &r, &g, &b);
    return {r, g, b};
}

Vec3 uniformDirection(std::mt19937_64& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const PclV3 d = sampling_uniform_sphere(u(rng), u(rng));
    return {d.x, d.y, d.z};
}

PclMedium medium(Vec3 sigmaA, Vec3 sigmaS, float g) {
    PclMedium m{};
    m.sigmaA[0] = sigmaA.x, m.sigmaA[1] = sigmaA.y, m.sigmaA[2] = sigmaA.z;
    m.sigmaS[0] = sigmaS.x, m.sigmaS[1] = sigmaS.y, m.sigmaS[2] = sigmaS.z;
    m.g = g;
    return m;
}

PclVolumeSegment segment(Vec3 o, Vec3 d, float length, int32_t mediumIndex, uint32_t record,
                         Vec3 throughput = Vec3(1.0f)) {
    PclVolumeSegment s{};
    s.ox = o.x, s.oy = o.y, s.oz = o.z;
    const Vec3 n = normalize(d);
    s.dx = n.x, s.dy = n.y, s.dz = n.z;
    s.length = length;
    s.throughput[0] = throughput.x, s.throughput[1] = throughput.y, s.throughput[2] = throughput.z;
    s.medium = mediumIndex;
    s.record = record;
    return s;
}

// One segment per record.
VolumeSegments oneEach(const std::vector<PclVolumeSegment>& list) {
    VolumeSegments s;
    s.sampleCount = uint32_t(list.size());
    s.maxSegments = 1;
    s.segments = list;
    s.counts.assign(list.size(), 1u);
    return s;
}

double channel(const PclRadiance& r, int c) { return c == 0 ? r.r : (c == 1 ? r.g : r.b); }

// The largest relative difference over the channels of a device and a twin value (0 where both
// are 0); a device value that is not finite reads as infinitely far.
double relativeDifference(const PclRadiance& d, const PclRadiance& t) {
    double rel = 0;
    for (int c = 0; c < 3; ++c) {
        if (!std::isfinite(channel(d, c))) return std::numeric_limits<double>::infinity();
        const double m = std::max(std::fabs(channel(d, c)), std::fabs(channel(t, c)));
        if (m > 0) rel = std::max(rel, std::fabs(channel(d, c) - channel(t, c)) / m);
    }
    return rel;
}

// ∫_0^ℓ e^{−σt t} dt and ∫_0^ℓ e^{−2σt t} dt.
double trIntegral(double sigmaT, double length, double power = 1.0) {
    const double s = power * sigmaT;
    return s > 0.0 ? (1.0 - std::exp(-s * length)) / s : length;
}

// E[p] and E[p²] of the HG phase over the photons' decoded directions against the eye direction
// (−d): the exact moments of what the estimator weighs, computed from the photons themselves.
struct PhaseMoments {
    double mean = 0, meanSquare = 0;
};
PhaseMoments phaseMoments(const std::vector<PclPhoton>& photons, Vec3 d, double g) {
    PhaseMoments m;
    for (const PclPhoton& p : photons) {
        const PclV3 w = photon_dir_decode(p.packed);
        const double ph = referenceBeamPhase(double(w.x) * d.x + double(w.y) * d.y + double(w.z) * d.z, g);
        m.mean += ph;
        m.meanSquare += ph * ph;
    }
    m.mean /= double(photons.size());
    m.meanSquare /= double(photons.size());
    return m;
}

// ∫ K² dA over the disc.
double kernelSquareIntegral(BeamKernel k, double r) {
    return (k == BeamKernel::Box ? 1.0 : 9.0 / 5.0) / (kPiD * r * r);
}

// Photons uniform in the unit cube, equal power, directions uniform (isotropic) or all along
// `collimated` when it is nonzero; bounce 1.
std::vector<PclPhoton> boxPhotons(size_t n, Vec3 totalPower, Vec3 collimated, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclPhoton> out(n);
    const bool iso = collimated.x == 0.0f && collimated.y == 0.0f && collimated.z == 0.0f;
    for (PclPhoton& p : out) {
        const Vec3 x(u(rng), u(rng), u(rng));
        p = volumePhoton(x, iso ? uniformDirection(rng) : collimated, totalPower / float(n));
    }
    return out;
}

// Segments along +x through the cube's interior, on a 5 × 5 grid of (y, z) 0.15 apart (more
// than 2r apart, so their photons are disjoint and the estimates independent).
std::vector<PclVolumeSegment> gridSegments(int32_t mediumIndex, float x0, float length) {
    std::vector<PclVolumeSegment> out;
    for (int a = 0; a < 5; ++a)
        for (int b = 0; b < 5; ++b)
            out.push_back(segment({x0, 0.2f + 0.15f * a, 0.2f + 0.15f * b}, {1, 0, 0}, length, mediumIndex,
                                  uint32_t(out.size())));
    return out;
}

// ---- (a) kernel vs twin ------------------------------------------------------------------

TEST(VolumeEstimate, KernelMatchesTwinOnRandomPhotonsAndSegments) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclPhoton> photons;
    for (int j = 0; j < 60000; ++j) {
        const uint32_t bounce = uint32_t(u(rng) * 3.0f);
        const uint32_t flags = u(rng) < 0.3f ? PCL_PHOTON_AFTER_SPECULAR : PCL_PHOTON_AFTER_DIFFUSE;
        photons.push_back(volumePhoton({u(rng), u(rng), u(rng)}, uniformDirection(rng),
                                       {u(rng) * 1e-4f, u(rng) * 1e-4f, u(rng) * 1e-4f}, bounce, flags));
    }
    const std::vector<PclMedium> media = {medium({0.1f, 0.2f, 0.4f}, {0.9f, 0.6f, 0.3f}, 0.6f),
                                          medium({0.0f, 0.0f, 0.0f}, {2.0f, 2.0f, 2.0f}, -0.3f)};
    // Records of 0..3 segments in random places, directions and media (vacuum included), some
    // leaving the cube, some of length 0.
    VolumeSegments s;
    s.sampleCount = 3000;
    s.maxSegments = 3;
    s.segments.assign(size_t(s.sampleCount) * s.maxSegments, PclVolumeSegment{});
    s.counts.assign(s.sampleCount, 0u);
    for (uint32_t i = 0; i < s.sampleCount; ++i) {
        s.counts[i] = uint32_t(u(rng) * 4.0f) % 4;
        for (uint32_t k = 0; k < s.counts[i]; ++k) {
            const int32_t m = int32_t(u(rng) * 3.0f) - 1;  // -1 (vacuum), 0, 1
            const float len = u(rng) < 0.05f ? 0.0f : 1.5f * u(rng);
            s.segments[size_t(k) * s.sampleCount + i] =
                segment({1.2f * u(rng) - 0.1f, 1.2f * u(rng) - 0.1f, 1.2f * u(rng) - 0.1f}, uniformDirection(rng), len,
                        m, i, {u(rng), u(rng), u(rng)});
        }
    }
    for (BeamKernel kernel : {BeamKernel::Box, BeamKernel::Biweight})
        for (int skip = 0; skip < 4; ++skip) {
            VolumeEstimateSettings settings;
            settings.radius = 0.04f;
            settings.kernel = kernel;
            settings.skipDirect = (skip & 1) != 0;
            settings.skipSpecularPaths = (skip & 2) != 0;
            const std::vector<PclRadiance> d = volumeEstimateOnDevice(test::testDevice(), photons, settings, s, media);
            const std::vector<PclRadiance> t = referenceVolumeEstimate(photons, settings, s, media);
            ASSERT_EQ(d.size(), t.size());
            size_t matched = 0, nonzero = 0;
            double worst = 0;
            for (size_t i = 0; i < t.size(); ++i) {
                const double rel = relativeDifference(d[i], t[i]);
                ASSERT_TRUE(std::isfinite(rel)) << "record " << i;
                worst = std::max(worst, rel);
                matched += rel <= 1e-4;
                nonzero += t[i].r != 0.0f;
            }
            std::printf("[figure] kernel %d skip %d: %zu/%zu records within 1e-4 (%zu nonzero), max rel %.2e\n",
                        int(kernel), skip, matched, t.size(), nonzero, worst);
            // A photon at d ≈ r or t_p ≈ 0, ℓ may fall either side in float: at most 0.1 %.
            EXPECT_GE(double(matched), 0.999 * double(t.size()));
            EXPECT_GT(nonzero, t.size() / 4);
        }
}

TEST(VolumeEstimate, TwinSearchFindsWhatBruteForceFinds) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclPhoton> photons;
    for (int j = 0; j < 5000; ++j)
        photons.push_back(volumePhoton({u(rng), u(rng), u(rng)}, uniformDirection(rng), {1e-3f, 2e-3f, 3e-3f}));
    const std::vector<PclMedium> media = {medium({0.3f, 0.3f, 0.3f}, {0.5f, 1.0f, 1.5f}, 0.4f)};
    std::vector<PclVolumeSegment> list;
    for (uint32_t i = 0; i < 200; ++i)
        list.push_back(segment({u(rng), u(rng), u(rng)}, uniformDirection(rng), u(rng), 0, i));
    VolumeEstimateSettings settings;
    settings.radius = 0.07f;
    const std::vector<PclRadiance> t = referenceVolumeEstimate(photons, settings, oneEach(list), media);
    for (size_t i = 0; i < list.size(); ++i) {
        const Vec3 b = referenceBeamEstimateBruteForce(photons, settings, list[i], media[0]);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(channel(t[i], c), b[c], 1e-5 * std::fabs(b[c]) + 1e-12) << i;
    }
}

// ---- (b) closed form: the beam estimate in a box of known density ----------------------

// Photons uniform in the unit cube (total power Φ), segments through it along +x: E[L] = ρ_Φ E[p]
// ∫_0^ℓ Tr dt with ρ_Φ = Φ (the cube's volume is 1). Var[L] ≈ N ΔΦ² E[p²] ∫K² dA ∫Tr² dt per
// segment (a Poisson sum); the mean over 25 independent segments must lie within 4 σ of E[L].
void expectBeamMatchesDensity(Vec3 collimated, float g, BeamKernel kernel, bool onDevice) {
    const size_t n = 400000;
    const std::vector<PclPhoton> photons = boxPhotons(n, {2.0f, 1.0f, 0.5f}, collimated, 11);
    const Vec3 phi = decodedPower(photons[0]);  // every photon has the same power
    const Vec3 sigmaT(0.5f, 1.0f, 2.0f);
    const std::vector<PclMedium> media = {medium(sigmaT * 0.25f, sigmaT * 0.75f, g)};
    const float length = 0.8f;
    const std::vector<PclVolumeSegment> list = gridSegments(0, 0.1f, length);
    VolumeEstimateSettings settings;
    settings.radius = 0.05f;
    settings.kernel = kernel;
    const std::vector<PclRadiance> est =
        onDevice ? volumeEstimateOnDevice(test::testDevice(), photons, settings, oneEach(list), media)
                 : referenceVolumeEstimate(photons, settings, oneEach(list), media);
    const PhaseMoments pm = phaseMoments(photons, {1, 0, 0}, g);
    for (int c = 0; c < 3; ++c) {
        double mean = 0;
        for (const PclRadiance& r : est) mean += channel(r, c);
        mean /= double(est.size());
        const double rho = double(n) * phi[c];
        const double expected = rho * pm.mean * trIntegral(sigmaT[c], length);
        const double var = double(n) * phi[c] * phi[c] * pm.meanSquare * kernelSquareIntegral(kernel, settings.radius) *
                           trIntegral(sigmaT[c], length, 2.0);
        const double sigma = std::sqrt(var / double(est.size()));
        std::printf("[figure] beam, %s, g %.1f, %s, %s, channel %d: mean %.5f, expected %.5f (%.2f %%), σ %.2f %%\n",
                    collimated.x != 0.0f ? "collimated" : "isotropic", g,
                    kernel == BeamKernel::Box ? "box" : "biweight", onDevice ? "kernel" : "twin", c, mean, expected,
                    100.0 * (mean / expected - 1.0), 100.0 * sigma / expected);
        EXPECT_NEAR(mean, expected, 4.0 * sigma) << "channel " << c;
    }
}

TEST(VolumeEstimate, BeamEqualsDensityTimesPhaseTimesTransmittanceIsotropic) {
    for (float g : {0.0f, 0.6f})
        for (BeamKernel k : {BeamKernel::Box, BeamKernel::Biweight})
            for (bool dev : {true, false}) expectBeamMatchesDensity({0, 0, 0}, g, k, dev);
}

// Every photon travels towards the eye (along −x against segments along +x): forward
// scattering, p(μ = 1) = (1 + g)/(4π (1 − g)²), 6.25× the isotropic 1/(4π) at g = 0.6; and
// away from it, p(μ = −1) = (1 − g)/(4π (1 + g)²): the phase's orientation.
TEST(VolumeEstimate, BeamWeighsThePhaseTowardTheEyeCollimated) {
    expectBeamMatchesDensity({-1, 0, 0}, 0.6f, BeamKernel::Biweight, true);
    expectBeamMatchesDensity({1, 0, 0}, 0.6f, BeamKernel::Biweight, true);
    expectBeamMatchesDensity({0, 1, 0}, 0.6f, BeamKernel::Box, false);
}

// ---- (b') per-photon radii (Jarosz, Zwicker & Jensen 2008) -------------------------------

// Photons in the unit cube, a quarter of them packed into a 0.2 cube (64× denser there): radii
// that differ by a factor of ~4 across the map.
std::vector<PclPhoton> unevenPhotons(size_t n, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclPhoton> out;
    for (size_t j = 0; j < n; ++j) {
        const bool dense = j % 4 == 0;
        const Vec3 x = dense ? Vec3(0.4f + 0.2f * u(rng), 0.4f + 0.2f * u(rng), 0.4f + 0.2f * u(rng))
                             : Vec3(u(rng), u(rng), u(rng));
        out.push_back(volumePhoton(x, uniformDirection(rng), {u(rng) * 1e-4f, u(rng) * 1e-4f, u(rng) * 1e-4f},
                                   1 + uint32_t(u(rng) * 2.0f)));
    }
    return out;
}

// The k-th neighbour distances on the device (kd-tree search) are the twin's (grid) bit for bit,
// and the brute force's (reference knn: the (k+1)-th nearest with the photon itself).
TEST(VolumePhotonRadii, KthNeighbourOnDeviceEqualsTwinAndBruteForce) {
    const std::vector<PclPhoton> photons = unevenPhotons(20000, 5);
    const uint32_t k = 16;
    const float rMax = 0.07f;  // about the sparse part's 16th-neighbour distance: some have fewer
    const std::vector<float> d = volumeKthNeighbourDist2(test::testDevice(), photons, k, rMax);
    const std::vector<float> t = referenceKthNeighbourDist2(photons, k, rMax);
    ASSERT_EQ(d.size(), t.size());
    size_t equal = 0, found = 0;
    for (size_t j = 0; j < t.size(); ++j) {
        equal += d[j] == t[j];
        found += t[j] >= 0.0f;
    }
    std::printf("[figure] k-th neighbour d²: %zu/%zu equal, %zu within rMax\n", equal, t.size(), found);
    EXPECT_EQ(equal, t.size());
    EXPECT_GT(found, t.size() / 2);
    EXPECT_LT(found, t.size());  // the sparse part has photons with fewer than k within rMax
    std::vector<PclKnnQuery> queries;
    for (size_t j = 0; j < photons.size(); j += 97)
        queries.push_back({photons[j].x, photons[j].y, photons[j].z, rMax * rMax, k + 1, 0, 0, 0});
    const ReferenceKnn b = referenceKnnBruteForce(photons, queries);
    for (size_t q = 0; q < queries.size(); ++q) EXPECT_EQ(t[q * 97], b.counts[q] == k + 1 ? b.radius2[q] : -1.0f) << q;
}

TEST(VolumePhotonRadii, ClampAndShrink) {
    const std::vector<float> r2 = clampVolumePhotonRadii2({-1.0f, 0.0f, 0.0004f, 0.01f, 1.0f, NAN}, 0.01f, 0.1f, 0.5f);
    const std::vector<float> expected = {0.005f, 0.00005f, 0.0002f, 0.005f, 0.005f, 0.005f};
    ASSERT_EQ(r2.size(), expected.size());
    for (size_t j = 0; j < r2.size(); ++j) EXPECT_FLOAT_EQ(r2[j], expected[j]) << j;
    const float reach = volumeReach(r2);
    EXPECT_GE(reach * reach, 0.005f);
    EXPECT_LT(reach, std::sqrt(0.005f) * 1.00001f);
    EXPECT_THROW(clampVolumePhotonRadii2({1.0f}, 0.2f, 0.1f, 1.0f), InternalError);
    EXPECT_THROW(clampVolumePhotonRadii2({1.0f}, 0.1f, 0.2f, 0.0f), InternalError);
}

// The kernel with per-photon radii against its twin, and the twin's grid search against the
// brute force over every photon, on the uneven map (both kernels, both skips).
TEST(VolumePhotonRadii, KernelMatchesTwinAndBruteForce) {
    std::vector<PclPhoton> photons = unevenPhotons(60000, 9);
    for (size_t j = 0; j < photons.size(); j += 5) photons[j].packed |= PCL_PHOTON_AFTER_SPECULAR;
    const float r0 = defaultVolumeRadius(photons, Bounds3{}, 16);
    const std::vector<float> r2 =
        clampVolumePhotonRadii2(referenceKthNeighbourDist2(photons, 16, 2.0f * r0), 0.25f * r0, 2.0f * r0, 0.7f);
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclVolumeSegment> list;
    for (uint32_t i = 0; i < 2000; ++i)
        list.push_back(segment({1.2f * u(rng) - 0.1f, 1.2f * u(rng) - 0.1f, 1.2f * u(rng) - 0.1f},
                               uniformDirection(rng), 1.2f * u(rng), 0, i, {u(rng), u(rng), u(rng)}));
    const std::vector<PclMedium> media = {medium({0.1f, 0.2f, 0.4f}, {0.9f, 0.6f, 0.3f}, 0.5f)};
    for (BeamKernel kernel : {BeamKernel::Box, BeamKernel::Biweight})
        for (bool skip : {false, true}) {
            VolumeEstimateSettings settings;
            settings.photonRadius2 = r2;
            settings.radius = volumeReach(r2);
            settings.kernel = kernel;
            settings.skipDirect = settings.skipSpecularPaths = skip;
            const std::vector<PclRadiance> d =
                volumeEstimateOnDevice(test::testDevice(), photons, settings, oneEach(list), media);
            const std::vector<PclRadiance> t = referenceVolumeEstimate(photons, settings, oneEach(list), media);
            size_t matched = 0, nonzero = 0;
            for (size_t i = 0; i < t.size(); ++i) {
                const double rel = relativeDifference(d[i], t[i]);
                ASSERT_TRUE(std::isfinite(rel)) << "record " << i;
                matched += rel <= 1e-4;
                nonzero += t[i].r != 0.0f;
            }
            std::printf("[figure] per-photon radii, kernel %d skip %d: %zu/%zu within 1e-4, %zu nonzero\n", int(kernel),
                        int(skip), matched, t.size(), nonzero);
            EXPECT_GE(double(matched), 0.999 * double(t.size()));
            EXPECT_GT(nonzero, t.size() / 4);
            for (size_t i = 0; i < list.size(); i += 40) {
                const Vec3 b = referenceBeamEstimateBruteForce(photons, settings, list[i], media[0]);
                for (int c = 0; c < 3; ++c) {
                    const double bt = double(b[c]) * list[i].throughput[c];  // the brute force has no throughput
                    EXPECT_NEAR(channel(t[i], c), bt, 1e-5 * std::fabs(bt) + 1e-12) << i;
                }
            }
        }
}

// Uniform density with each photon's radius from its own 16th neighbour: the kernel over each
// photon's disc integrates to 1 whatever its radius, so E[L] = ρ_Φ E[p] ∫ Tr dt as with one
// radius; Var ≈ ΔΦ² E[p²] ∫Tr² Σ_p ∫K_p² dA / (disc areas): within 4 σ over 25 segments.
TEST(VolumePhotonRadii, BeamOnUniformDensityEqualsDensityTimesPhase) {
    const size_t n = 400000;
    const std::vector<PclPhoton> photons = boxPhotons(n, {2.0f, 1.0f, 0.5f}, {0, 0, 0}, 21);
    const Vec3 phi = decodedPower(photons[0]);
    const Vec3 sigmaT(0.5f, 1.0f, 2.0f);
    const float g = 0.6f;
    const std::vector<PclMedium> media = {medium(sigmaT * 0.25f, sigmaT * 0.75f, g)};
    const float length = 0.8f;
    const std::vector<PclVolumeSegment> list = gridSegments(0, 0.1f, length);
    const float r0 = defaultVolumeRadius(photons, Bounds3{}, 16);
    VolumeEstimateSettings settings;
    settings.photonRadius2 = clampVolumePhotonRadii2(
        volumeKthNeighbourDist2(test::testDevice(), photons, 16, 2.0f * r0), 0.25f * r0, 2.0f * r0, 1.0f);
    settings.radius = volumeReach(settings.photonRadius2);
    settings.kernel = BeamKernel::Biweight;
    const std::vector<PclRadiance> est =
        volumeEstimateOnDevice(test::testDevice(), photons, settings, oneEach(list), media);
    const PhaseMoments pm = phaseMoments(photons, {1, 0, 0}, g);
    double k2 = 0;  // the mean over photons of ∫K_p² dA
    for (float r2 : settings.photonRadius2) k2 += kernelSquareIntegral(settings.kernel, std::sqrt(double(r2)));
    k2 /= double(n);
    for (int c = 0; c < 3; ++c) {
        double mean = 0;
        for (const PclRadiance& r : est) mean += channel(r, c);
        mean /= double(est.size());
        const double expected = double(n) * phi[c] * pm.mean * trIntegral(sigmaT[c], length);
        const double var = double(n) * phi[c] * phi[c] * pm.meanSquare * k2 * trIntegral(sigmaT[c], length, 2.0);
        const double sigma = std::sqrt(var / double(est.size()));
        std::printf("[figure] per-photon radii (r0 %.4f), channel %d: mean %.5f, expected %.5f (%.2f %%), σ %.2f %%\n",
                    r0, c, mean, expected, 100.0 * (mean / expected - 1.0), 100.0 * sigma / expected);
        EXPECT_NEAR(mean, expected, 4.0 * sigma) << "channel " << c;
    }
}

// ---- (c) the point estimate ---------------------------------------------------------------

// At 64 points 0.2 apart (r = 0.08): E = ρ_Φ E[p]; Var ≈ N ΔΦ² E[p²] / V_ball per point.
TEST(VolumePointEstimate, EqualsDensityTimesPhase) {
    const size_t n = 400000;
    for (float g : {0.0f, 0.6f}) {
        const std::vector<PclPhoton> photons = boxPhotons(n, {2.0f, 1.0f, 0.5f}, {0, 0, 0}, 5);
        const Vec3 phi = decodedPower(photons[0]);
        VolumeEstimateSettings settings;
        settings.radius = 0.08f;
        const Vec3 towardEye = normalize(Vec3(1, 2, 3));
        double sum[3] = {0, 0, 0};
        int points = 0;
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b)
                for (int c = 0; c < 4; ++c, ++points) {
                    const Vec3 x(0.2f + 0.2f * a, 0.2f + 0.2f * b, 0.2f + 0.2f * c);
                    const Vec3 l = referenceVolumePointEstimate(photons, settings, x, towardEye, g);
                    for (int ch = 0; ch < 3; ++ch) sum[ch] += l[ch];
                }
        const PhaseMoments pm = phaseMoments(photons, -towardEye, g);  // μ = (−w)·ω_e = w·(−ω_e)
        const double ball = 4.0 / 3.0 * kPiD * std::pow(double(settings.radius), 3);
        for (int ch = 0; ch < 3; ++ch) {
            const double mean = sum[ch] / points;
            const double expected = double(n) * phi[ch] * pm.mean;
            const double sigma = std::sqrt(double(n) * phi[ch] * phi[ch] * pm.meanSquare / ball / points);
            std::printf("[figure] point estimate g %.1f channel %d: mean %.5f expected %.5f (%.2f %%), σ %.2f %%\n", g,
                        ch, mean, expected, 100.0 * (mean / expected - 1.0), 100.0 * sigma / expected);
            EXPECT_NEAR(mean, expected, 4.0 * sigma);
        }
    }
}

// ∫ Tr L_s dt along a segment (point estimates, midpoint rule) agrees with the beam estimate's
// expectation: both estimate the same integral (a consistency check of their conventions).
TEST(VolumePointEstimate, IntegratedAlongASegmentMatchesTheBeam) {
    const size_t n = 200000;
    const std::vector<PclPhoton> photons = boxPhotons(n, {1.0f, 1.0f, 1.0f}, {0, 0, -1}, 9);
    const PclMedium m = medium({0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}, 0.5f);
    const PclVolumeSegment s = segment({0.5f, 0.5f, 0.1f}, {0, 0, 1}, 0.8f, 0, 0);
    VolumeEstimateSettings settings;
    settings.radius = 0.1f;
    const Vec3 beam = referenceBeamEstimateBruteForce(photons, settings, s, m);
    double integral = 0;
    const int steps = 8;  // points 0.1 apart, each with its own photons (r = 0.1: balls just touch)
    for (int k = 0; k < steps; ++k) {
        const float t = (k + 0.5f) * s.length / steps;
        const Vec3 l = referenceVolumePointEstimate(photons, settings, {s.ox, s.oy, s.oz + t}, {0, 0, -1}, m.g);
        integral += l.x * std::exp(-1.0 * t) * s.length / steps;
    }
    std::printf("[figure] beam %.4f, integrated point estimates %.4f\n", beam.x, integral);
    EXPECT_NEAR(beam.x, integral, 0.1 * integral);
}

// ---- (d) skip flags ---------------------------------------------------------------------

TEST(VolumeEstimate, SkipFlagsDropExactlyTheirPhotons) {
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclPhoton> all, direct, indirect, specularPaths, others;
    for (int j = 0; j < 40000; ++j) {
        const uint32_t bounce = uint32_t(u(rng) * 3.0f);
        const bool lsv = bounce > 0 && u(rng) < 0.4f;
        const uint32_t flags =
            lsv ? PCL_PHOTON_AFTER_SPECULAR
                : (bounce > 0 ? PCL_PHOTON_AFTER_DIFFUSE | (u(rng) < 0.5f ? PCL_PHOTON_AFTER_SPECULAR : 0u) : 0u);
        const PclPhoton p =
            volumePhoton({u(rng), u(rng), u(rng)}, uniformDirection(rng), {1e-3f, 1e-3f, 1e-3f}, bounce, flags);
        all.push_back(p);
        (bounce == 0 ? direct : indirect).push_back(p);
        (lsv ? specularPaths : others).push_back(p);
    }
    ASSERT_GT(direct.size(), 5000u);
    ASSERT_GT(specularPaths.size(), 5000u);
    const std::vector<PclMedium> media = {medium({0.2f, 0.2f, 0.2f}, {0.8f, 0.8f, 0.8f}, 0.3f)};
    const VolumeSegments s = oneEach(gridSegments(0, 0.1f, 0.8f));
    VolumeEstimateSettings plain, skipDirect, skipSpecular;
    plain.radius = skipDirect.radius = skipSpecular.radius = 0.06f;
    skipDirect.skipDirect = true;
    skipSpecular.skipSpecularPaths = true;
    Device& dev = test::testDevice();
    const auto dAll = volumeEstimateOnDevice(dev, all, plain, s, media);
    const auto dSkip = volumeEstimateOnDevice(dev, all, skipDirect, s, media);
    const auto dIndirect = volumeEstimateOnDevice(dev, indirect, plain, s, media);
    const auto dDirect = volumeEstimateOnDevice(dev, direct, plain, s, media);
    const auto dSkipSpec = volumeEstimateOnDevice(dev, all, skipSpecular, s, media);
    const auto dOthers = volumeEstimateOnDevice(dev, others, plain, s, media);
    const auto tSkip = referenceVolumeEstimate(all, skipDirect, s, media);
    const auto tIndirect = referenceVolumeEstimate(indirect, plain, s, media);
    const auto tSkipSpec = referenceVolumeEstimate(all, skipSpecular, s, media);
    const auto tOthers = referenceVolumeEstimate(others, plain, s, media);
    for (size_t i = 0; i < s.sampleCount; ++i) {
        // Skipping equals estimating the remaining photons alone (same photons, same float sums up
        // to order: the subset's grid sorts them differently).
        EXPECT_NEAR(dSkip[i].r, dIndirect[i].r, 1e-5 * dIndirect[i].r) << i;
        EXPECT_NEAR(dSkipSpec[i].r, dOthers[i].r, 1e-5 * dOthers[i].r) << i;
        EXPECT_NEAR(tSkip[i].r, tIndirect[i].r, 1e-6 * tIndirect[i].r) << i;
        EXPECT_NEAR(tSkipSpec[i].r, tOthers[i].r, 1e-6 * tOthers[i].r) << i;
        // and what it drops is the bounce-0 estimate.
        EXPECT_NEAR(dAll[i].r - dSkip[i].r, dDirect[i].r, 1e-4 * dAll[i].r) << i;
        EXPECT_GT(dDirect[i].r, 0.1f * dAll[i].r) << i;
    }
}

// ---- (e) convergence --------------------------------------------------------------------

// A density with curvature across the beams, ρ ∝ 1 + a((y − ½)² + (z − ½)²): the disc average
// is biased by a ρ₀ r²/2 (box kernel), the noise falls as 1/√(N r²). With r ∝ N^(−1/6) both fall
// as N^(−1/3) (a factor 0.25 over N = 12.5k → 800k). The RMS relative error over 49 segments
// and 4 independent maps per N must fall with a fitted log-log slope below −0.2, and by more
// than 2.5× from the first N to the last.
TEST(VolumeEstimate, ErrorFallsAsPhotonsGrowAndRadiusShrinks) {
    const double a = 8.0;
    const Vec3 total(1.0f, 1.0f, 1.0f);
    const std::vector<PclMedium> media = {medium({0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}, 0.0f)};
    std::vector<PclVolumeSegment> list;
    for (int b = 0; b < 7; ++b)
        for (int c = 0; c < 7; ++c)
            list.push_back(
                segment({0.15f, 0.2f + 0.1f * b, 0.2f + 0.1f * c}, {1, 0, 0}, 0.7f, 0, uint32_t(list.size())));
    std::vector<double> logN, logErr;
    for (int level = 0; level < 4; ++level) {
        const size_t n = size_t(12500) << (2 * level);
        const float r = 0.12f * float(std::pow(double(n) / 12500.0, -1.0 / 6.0));
        double se = 0;
        size_t samples = 0;
        for (int rep = 0; rep < 4; ++rep) {
            std::mt19937_64 rng(100 + 10 * level + rep);
            std::uniform_real_distribution<float> u(0.0f, 1.0f);
            std::vector<PclPhoton> photons;
            photons.reserve(n);
            while (photons.size() < n) {
                const Vec3 x(u(rng), u(rng), u(rng));
                const double f = 1.0 + a * ((x.y - 0.5) * (x.y - 0.5) + (x.z - 0.5) * (x.z - 0.5));
                if (u(rng) * (1.0 + a * 0.5) < f)
                    photons.push_back(volumePhoton(x, uniformDirection(rng), total / float(n)));
            }
            VolumeEstimateSettings settings;
            settings.radius = r;
            settings.kernel = BeamKernel::Box;
            const auto est = volumeEstimateOnDevice(test::testDevice(), photons, settings, oneEach(list), media);
            const double phi = decodedPower(photons[0]).x;
            for (size_t i = 0; i < list.size(); ++i, ++samples) {
                const double y = list[i].oy - 0.5, z = list[i].oz - 0.5;
                const double rho = double(n) * phi * (1.0 + a * (y * y + z * z)) / (1.0 + a / 6.0);
                const double expected = rho / (4.0 * kPiD) * trIntegral(1.0, list[i].length);
                se += std::pow(est[i].r / expected - 1.0, 2.0);
            }
        }
        const double rms = std::sqrt(se / double(samples));
        std::printf("[figure] convergence: N %zu, r %.4f, RMS relative error %.4f\n", n, r, rms);
        logN.push_back(std::log(double(n)));
        logErr.push_back(std::log(rms));
    }
    double mx = 0, my = 0;
    for (size_t i = 0; i < logN.size(); ++i) mx += logN[i], my += logErr[i];
    mx /= double(logN.size()), my /= double(logN.size());
    double sxy = 0, sxx = 0;
    for (size_t i = 0; i < logN.size(); ++i) sxy += (logN[i] - mx) * (logErr[i] - my), sxx += std::pow(logN[i] - mx, 2);
    const double slope = sxy / sxx;
    std::printf("[figure] convergence slope %.3f (expected about −1/3)\n", slope);
    EXPECT_LT(slope, -0.2);
    EXPECT_LT(logErr.back(), logErr.front() - std::log(2.5));
}

// ---- (f) robustness ---------------------------------------------------------------------

TEST(VolumeEstimate, EmptyMapAndDegenerateSegmentsGiveFiniteZeros) {
    const std::vector<PclMedium> media = {medium({0.1f, 0.1f, 0.1f}, {0.9f, 0.9f, 0.9f}, 0.99f)};
    const VolumeSegments s =
        oneEach({segment({0, 0, 0}, {1, 0, 0}, 1.0f, 0, 0), segment({0, 0, 0}, {0, 1, 0}, 0.0f, 0, 1),
                 segment({0, 0, 0}, {0, 0, 1}, 1.0f, PCL_NO_MEDIUM, 2)});
    VolumeEstimateSettings settings;
    settings.radius = 0.1f;
    for (const auto& out : {volumeEstimateOnDevice(test::testDevice(), {}, settings, s, media),
                            referenceVolumeEstimate({}, settings, s, media)})
        for (const PclRadiance& r : out) {
            EXPECT_EQ(r.r, 0.0f);
            EXPECT_EQ(r.g, 0.0f);
            EXPECT_EQ(r.b, 0.0f);
        }
    // Photons on the line itself (d = 0), at t = 0 and t = ℓ, of zero power, travelling exactly
    // towards the eye with g = 0.99 (the phase's peak): finite, and the same on both sides;
    // the zero-length and vacuum segments stay 0.
    std::vector<PclPhoton> photons = {volumePhoton({0, 0, 0}, {-1, 0, 0}, {1, 1, 1}),
                                      volumePhoton({1, 0, 0}, {-1, 0, 0}, {1, 1, 1}),
                                      volumePhoton({0.5f, 0, 0}, {-1, 0, 0}, {0, 0, 0}),
                                      volumePhoton({0.5f, 0.05f, 0}, {1, 0, 0}, {1e-30f, 1e30f, 1})};
    const auto d = volumeEstimateOnDevice(test::testDevice(), photons, settings, s, media);
    const auto t = referenceVolumeEstimate(photons, settings, s, media);
    for (size_t i = 0; i < 3; ++i)
        for (int c = 0; c < 3; ++c) {
            EXPECT_TRUE(std::isfinite(channel(d[i], c))) << i;
            // 1e-2: at g = 0.99 and μ ≈ 1 − 9e-5, an ulp of the kernel's float μ moves p by 1e-3.
            EXPECT_NEAR(channel(d[i], c), channel(t[i], c), 1e-2 * std::fabs(channel(t[i], c))) << i << " " << c;
        }
    EXPECT_GT(d[0].r, 0.0f);
    EXPECT_EQ(d[1].r, 0.0f);
    EXPECT_EQ(d[2].r, 0.0f);
}

TEST(VolumeEstimate, RefusesBadInput) {
    const std::vector<PclMedium> media = {medium({0.1f, 0.1f, 0.1f}, {0.9f, 0.9f, 0.9f}, 0.0f)};
    const std::vector<PclPhoton> photons = {volumePhoton({0, 0, 0}, {1, 0, 0}, {1, 1, 1})};
    VolumeEstimateSettings settings;
    settings.radius = 0.1f;
    VolumeSegments s = oneEach({segment({0, 0, 0}, {1, 0, 0}, 1.0f, 0, 0)});
    EXPECT_NO_THROW(referenceVolumeEstimate(photons, settings, s, media));
    VolumeSegments badMedium = s;
    badMedium.segments[0].medium = 1;
    VolumeSegments badCount = s;
    badCount.counts[0] = 2;
    VolumeSegments badRecord = s;
    badRecord.segments[0].record = 5;
    for (const VolumeSegments* bad : {&badMedium, &badCount, &badRecord}) {
        EXPECT_THROW(referenceVolumeEstimate(photons, settings, *bad, media), InternalError);
        EXPECT_THROW(volumeEstimateOnDevice(test::testDevice(), photons, settings, *bad, media), InternalError);
    }
    std::vector<PclPhoton> surface = photons;
    surface[0].packed &= ~PCL_PHOTON_VOLUME;
    EXPECT_THROW(volumeEstimateOnDevice(test::testDevice(), surface, settings, s, media), InternalError);
    std::vector<PclPhoton> nowhere = photons;
    nowhere[0].y = NAN;
    EXPECT_THROW(referenceVolumeEstimate(nowhere, settings, s, media), InternalError);
    settings.radius = 0.0f;
    EXPECT_THROW(referenceVolumeEstimate(photons, settings, s, media), InternalError);
}

// ---- the radius ---------------------------------------------------------------------------

// Uniform density n: the k-th nearest neighbour's ball holds k photons, r ≈ (3k/(4π n))^(1/3).
TEST(VolumeEstimateSettings, DefaultRadiusHoldsKPhotonsAndShrinksProgressively) {
    const size_t n = 100000;
    const std::vector<PclPhoton> photons = boxPhotons(n, {1, 1, 1}, {0, 0, 0}, 17);
    const float r = defaultVolumeRadius(photons);
    const double expected = std::cbrt(3.0 * 32.0 / (4.0 * kPiD * double(n)));
    std::printf("[figure] default radius %.5f, (3k/(4πn))^(1/3) = %.5f\n", r, expected);
    // Medians of 128 samples near the faces (where the ball is cut) bias it up by a few percent.
    EXPECT_NEAR(r, expected, 0.1 * expected);
    EXPECT_EQ(defaultVolumeRadius(std::vector<PclPhoton>(photons.begin(), photons.begin() + 32), Bounds3{}, 32), 0.0f);
    // A region: only the photons inside it are sampled; the sparse ones outside do not count.
    std::vector<PclPhoton> spread = photons;
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<float> u(2.0f, 20.0f);
    for (int j = 0; j < 300000; ++j) spread.push_back(volumePhoton({u(rng), u(rng), u(rng)}, {0, 0, 1}, {1, 1, 1}));
    Bounds3 cube;
    cube.extend(Vec3(0.0f));
    cube.extend(Vec3(1.0f));
    const float inCube = defaultVolumeRadius(spread, cube);
    std::printf("[figure] with 3x as many sparse photons outside: over all %.4f, over the cube %.4f\n",
                defaultVolumeRadius(spread), inCube);
    EXPECT_NEAR(inCube, r, 0.02f * r);
    EXPECT_GT(defaultVolumeRadius(spread), 5.0f * r);
    // r²_{i+1} = r²_i (i + α)/(i + 1).
    EXPECT_FLOAT_EQ(shrinkVolumeRadius2(1.0f, 1, 0.5f), 0.75f);
    EXPECT_FLOAT_EQ(shrinkVolumeRadius2(0.75f, 2, 0.5f), 0.625f);
    EXPECT_THROW(shrinkVolumeRadius2(1.0f, 1, 0.0f), InternalError);
    EXPECT_THROW(shrinkVolumeRadius2(1.0f, 0, 0.5f), InternalError);
}

// ---- the check on the media scenes ------------------------------------------------------

TEST(VolumeEstimateCheck, PassesOnCornellFogAndHazyRoom) {
    for (const char* name : {"media/cornell-fog.json", "media/hazy-room.json"}) {
        const test::BuiltScene b = test::shippedScene(name, 64, 64);
        VolumeEstimateCheckOptions o;
        o.photons = 20000;
        o.records = 1500;
        const VolumeEstimateCheckReport r = checkVolumeEstimate(test::testDevice(), b.scene, b.geometry, b.buffers, o);
        std::printf("%s\n%s", name, r.table().c_str());
        EXPECT_TRUE(r.passed()) << name;
        EXPECT_GE(r.rows.size(), 4u) << name;
    }
}

}  // namespace
}  // namespace pcl
