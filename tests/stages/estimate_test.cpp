// The irradiance estimate (kernels/estimate.cl, pipeline/estimate) against its twin
// (reference/estimate) and against analytic densities:
//   a. twin cross-check per filter and structure on a random map and on cornell-box surface
//      points (checkEstimate): the same photons found and used, irradiance within 1e-5 relative
//      (exp, division and sqrt of the device and the host may differ by an ulp), no NaN;
//   b. uniform density on a plane: mean within 0.5 % of the analytic expectation, relative
//      spread within 20 % of its expectation, for every filter;
//   c. boundary bias: edge and corner of uniformly lit squares read 0.5 and 0.25 of the interior
//      within 0.02;
//   d. leak: two rooms sharing a thin wall, lit in one: exactly zero in the other with the
//      visibility test; the shared wall's far face reads zero by the normal test alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <random>
#include <vector>

#include "check/estimate.h"
#include "check/on_device.h"
#include "common/two_rooms.h"
#include "device_fixture.h"
#include "photon_test_scenes.h"
#include "pipeline/device_scene.h"
#include "pipeline/estimate.h"
#include "pipeline/photon_pass.h"
#include "reference/estimate.h"
#include "reference/knn.h"
#include "scene/load_scene.h"
#include "shared/sampling.h"

namespace pcl {
namespace {

const std::vector<KnnStructure> kStructures = {KnnStructure::KdTree, KnnStructure::HashGrid};

PclPhoton makePhoton(Vec3 p, Vec3 incoming, Vec3 normal, Vec3 power) {
    PclPhoton ph{};
    ph.x = p.x, ph.y = p.y, ph.z = p.z;
    ph.rgbe = photon_rgbe_encode(power.x, power.y, power.z);
    ph.packed = photon_dir_encode(incoming.x, incoming.y, incoming.z);
    ph.normal = photon_normal_encode(normal.x, normal.y, normal.z);
    return ph;
}

PclEstimateQuery makeQuery(Vec3 p, Vec3 n, float maxRadius, uint32_t k) {
    PclEstimateQuery q{};
    q.x = p.x, q.y = p.y, q.z = p.z;
    q.nx = n.x, q.ny = n.y, q.nz = n.z;
    q.maxRadius2 = maxRadius * maxRadius;
    q.k = k;
    return q;
}

bool finite(const PclEstimate& e) { return std::isfinite(e.r) && std::isfinite(e.g) && std::isfinite(e.b); }

// ---- Filter moments over the unit disc (for the analytic expectations) ------------------
// E_disc[f] = 2 ∫₀¹ f(u) u du, by Simpson's rule.
double discMean(const std::function<double(double)>& f) {
    const int n = 20000;
    double s = 0.0;
    for (int i = 0; i <= n; ++i) {
        const double u = double(i) / n;
        const double c = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        s += c * f(u) * u;
    }
    return 2.0 * s / (3.0 * n);
}

double weight(EstimateFilter f, double coneK, double u) {
    const double beta = double(PCL_GAUSSIAN_BETA);
    switch (f) {
        case EstimateFilter::Box: return 1.0;
        case EstimateFilter::Cone: return 1.0 - u / coneK;
        case EstimateFilter::Epanechnikov: return 1.0 - u * u;
        case EstimateFilter::Gaussian: return 1.0 - (1.0 - std::exp(-beta * u * u / 2.0)) / (1.0 - std::exp(-beta));
    }
    return 1.0;
}

TEST(EstimateFilters, NamesParseAndUnknownNamesListTheValidOnes) {
    for (EstimateFilter f : allEstimateFilters()) EXPECT_EQ(parseEstimateFilter(estimateFilterName(f)), f);
    try {
        parseEstimateFilter("tent");
        FAIL() << "no InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("box|cone|epanechnikov|gaussian"), std::string::npos) << e.what();
    }
}

// Each filter's norm is the mean of its weight over the unit disc, so a uniform density reads
// right; the Gaussian's exact norm (≈ 0.5786) replaces Jensen's α = 0.918.
TEST(EstimateFilters, NormIsTheMeanWeightOverTheUnitDisc) {
    for (EstimateFilter f : allEstimateFilters()) {
        const double m = discMean([&](double u) { return weight(f, double(1.1f), u); });
        EXPECT_NEAR(estimateFilterNorm(f, 1.1f), m, 1e-9) << estimateFilterName(f);
        std::printf("[figure] filter %-12s norm %.6f (quadrature %.6f)\n", estimateFilterName(f),
                    estimateFilterNorm(f, 1.1f), m);
    }
    EXPECT_NEAR(estimateFilterNorm(EstimateFilter::Gaussian, 1.1f), 0.5786, 5e-4);
}

// ---- a. Twin cross-check ------------------------------------------------------------------

void expectSame(const std::vector<PclEstimate>& twin, const std::vector<PclEstimate>& dev, const char* what,
                double* maxErr) {
    EstimateCheckRow row;
    compareEstimates(twin, dev, row);
    EXPECT_EQ(row.countMismatches, 0u) << what;
    EXPECT_EQ(row.radiusMismatches, 0u) << what;
    EXPECT_EQ(row.nans, 0u) << what;
    EXPECT_LE(row.maxRelError, kEstimateTolerance) << what;
    EXPECT_LE(row.nondirectError, kNondirectTolerance) << what;
    EXPECT_GT(row.nonzero, twin.size() / 10) << what << ": too few nonzero estimates to compare";
    *maxErr = std::max(*maxErr, row.maxRelError);
}

TEST(Estimate, MatchesTwinOnRandomMapForEveryFilterAndStructure) {
    Device& device = test::testDevice();
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::normal_distribution<float> g(0.0f, 1.0f);
    // Normals and incoming directions near the six axes, so the rejection tests both pass and fail.
    const Vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    auto nearAxis = [&](Vec3 a) { return normalize(a + Vec3(g(rng), g(rng), g(rng)) * 0.15f); };
    std::vector<PclPhoton> map(30000);
    for (auto& p : map) {
        const Vec3 n = nearAxis(axes[rng() % 6]);
        const Vec3 w = normalize(n + Vec3(g(rng), g(rng), g(rng)) * 0.7f);
        p = makePhoton(Vec3(u(rng), u(rng), u(rng)), w, n, Vec3(u(rng) + 0.01f, u(rng) * 3.0f, 0.5f * u(rng)));
        p.packed |= uint32_t(rng() % 3) << PCL_PHOTON_BOUNCE_SHIFT;  // a third straight from a light
    }
    const float rMax = 0.08f;
    std::vector<PclEstimateQuery> qs(3000);
    for (auto& q : qs) {
        q = makeQuery(Vec3(u(rng), u(rng), u(rng)), nearAxis(axes[rng() % 6]), rMax * std::sqrt(0.25f + 0.75f * u(rng)),
                      1 + rng() % 100);
    }
    qs[0].maxRadius2 = 0.0f;  // finds nothing (or only photons exactly there): exactly 0
    for (size_t i = 1; i < qs.size(); i += 3) qs[i].k |= PCL_QUERY_NONDIRECT;  // the photons that bounced alone
    const ReferenceKnn brute = referenceKnnBruteForce(map, estimateKnnQueries(qs));
    double maxErr = 0.0;
    for (KnnStructure s : kStructures) {
        const PhotonMapOnDevice built(device, map, s, rMax);
        for (EstimateFilter f : allEstimateFilters()) {
            EstimateSettings settings;
            settings.filter = f;
            const std::vector<PclEstimate> twin = referenceEstimateWithKnn(map, qs, brute, settings, nullptr);
            const EstimateResult dev = estimateOnDevice(device, built, qs, settings, nullptr);
            const std::string what = std::string(knnStructureName(s)) + " " + estimateFilterName(f);
            expectSame(twin, dev.values, what.c_str(), &maxErr);
            EXPECT_EQ(dev.values[0].r, 0.0f);
            EXPECT_EQ(dev.values[0].radius2, 0.0f);
        }
    }
    std::printf("[figure] estimate vs twin, random map (30k photons, 3000 queries, k 1..100): max rel diff %.2e\n",
                maxErr);
}

// PCL_QUERY_NONDIRECT: the estimate of the photons that bounced alone, over the same disc. Two
// photons at each point of a plane, one straight from a light (power 1), one after a bounce
// (0.25): the flagged estimate reads 0.25 / 1.25 of the full one, and the full estimate's
// nondirect word says the same (RGBE); device and twin alike.
TEST(Estimate, NondirectQueriesCountOnlyThePhotonsThatBounced) {
    Device& device = test::testDevice();
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclPhoton> map;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 p(u(rng), 0.0f, u(rng));
        map.push_back(makePhoton(p, Vec3(0, 1, 0), Vec3(0, 1, 0), Vec3(1.0f)));
        map.push_back(makePhoton(p, Vec3(0, 1, 0), Vec3(0, 1, 0), Vec3(0.25f)));
        map.back().packed |= 1u << PCL_PHOTON_BOUNCE_SHIFT;
    }
    std::vector<PclEstimateQuery> qs;
    for (int i = 0; i < 200; ++i) {
        qs.push_back(makeQuery(Vec3(0.2f + 0.6f * u(rng), 0.0f, 0.2f + 0.6f * u(rng)), Vec3(0, 1, 0), 0.1f, 50));
        qs.push_back(qs.back());
        qs.back().k |= PCL_QUERY_NONDIRECT;
    }
    const PhotonMapOnDevice built(device, map, KnnStructure::KdTree, 0.1f);
    EstimateSettings settings;
    settings.filter = EstimateFilter::Box;
    const EstimateResult dev = estimateOnDevice(device, built, qs, settings, nullptr);
    const std::vector<PclEstimate> twin = referenceEstimate(map, qs, settings, nullptr);
    double worst = 0.0, worstWord = 0.0;
    for (size_t i = 0; i < qs.size(); i += 2) {
        for (const std::vector<PclEstimate>* e : {&dev.values, &twin}) {
            const PclEstimate &all = (*e)[i], &later = (*e)[i + 1];
            ASSERT_GT(all.r, 0.0f);
            EXPECT_EQ(all.used, later.used);  // the same photons found and tested
            worst = std::max(worst, std::fabs(later.r / all.r - 0.2));
            float r, g, b;
            photon_rgbe_decode(all.nondirect, &r, &g, &b);
            worstWord = std::max(worstWord, std::fabs(r / later.r - 1.0));
        }
    }
    std::printf("[figure] nondirect estimate: flagged / full within %.4f of 0.2 (pairs split at the k-th), RGBE word "
                "within %.4f of the flagged estimate\n",
                worst, worstWord);
    EXPECT_LT(worst, 0.2 / 25.0);  // one photon of 50 on the wrong side of the k-th distance
    EXPECT_LT(worstWord, 1.0 / 128.0);
    EstimateCheckRow row;
    compareEstimates(twin, dev.values, row);
    EXPECT_TRUE(row.passed()) << row.maxRelError << " " << row.nondirectError;
}

// The lower-level call on buffers already on the device gives what the convenience gives.
TEST(Estimate, EstimateBuffersOnDeviceQueriesEqualsEstimateOnDevice) {
    Device& device = test::testDevice();
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclPhoton> map(5000);
    for (auto& p : map) p = makePhoton(Vec3(u(rng), u(rng), 0.0f), Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(1.0f));
    std::vector<PclEstimateQuery> qs(700);
    for (auto& q : qs) q = makeQuery(Vec3(u(rng), u(rng), 0.0f), Vec3(0, 0, 1), 0.1f, 20);
    const PhotonMapOnDevice built(device, map, KnnStructure::KdTree, 0.3f);
    const EstimateResult whole = estimateOnDevice(device, built, qs, {}, nullptr);
    cl::Buffer qb = device.upload(qs);
    cl::Buffer out = device.allocate<PclEstimate>(qs.size());
    EstimateTiming t = estimateBuffers(device, built, qb, qs.size(), 20, {}, nullptr, out);
    EXPECT_GE(t.batches, 1u);
    const std::vector<PclEstimate> again = device.download<PclEstimate>(out, qs.size());
    ASSERT_EQ(again.size(), whole.values.size());
    for (size_t i = 0; i < qs.size(); ++i) {
        EXPECT_EQ(again[i].r, whole.values[i].r);
        EXPECT_EQ(again[i].used, whole.values[i].used);
    }
    EXPECT_GE(estimateBatchQueries(device, 500), 1u);
}

// A per-buffer cap (Device::setBufferCap, --max-buffer-mib) only splits the queries into more
// batches: the estimates are the same.
TEST(Estimate, CappedBuffersSplitIntoBatchesWithTheSameEstimates) {
    Device device = test::testDevice();  // a copy: the cap stays with it
    std::mt19937 rng(6);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclPhoton> map(5000);
    for (auto& p : map) p = makePhoton(Vec3(u(rng), u(rng), 0.0f), Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(u(rng)));
    std::vector<PclEstimateQuery> qs(5000);
    for (auto& q : qs) q = makeQuery(Vec3(u(rng), u(rng), 0.0f), Vec3(0, 0, 1), 0.1f, 20);
    for (KnnStructure s : kStructures) {
        EstimateSettings settings;
        settings.structure = s;
        const EstimateResult whole = estimateOnDevice(test::testDevice(), map, qs, settings, nullptr);
        device.setBufferCap(size_t(1) << 20);
        const EstimateResult capped = estimateOnDevice(device, map, qs, settings, nullptr);
        EXPECT_EQ(whole.timing.batches, 1u);
        EXPECT_GE(capped.timing.batches, 3u) << "1 MiB cap, 20 × 8 B per query: batches of ≤ 1638";
        std::printf("[figure] estimate under a 1 MiB buffer cap (%s): %zu batches of %zu queries\n",
                    knnStructureName(s), capped.timing.batches, capped.timing.batchQueries);
        ASSERT_EQ(capped.values.size(), whole.values.size());
        for (size_t i = 0; i < qs.size(); ++i) {
            ASSERT_EQ(capped.values[i].r, whole.values[i].r) << i;
            ASSERT_EQ(capped.values[i].used, whole.values[i].used) << i;
        }
    }
}

// Through the hash grid, estimateBuffers clamps a radius above the grid's r_max to it (the
// grid finds every photon only within r_max): the same as asking r_max.
TEST(Estimate, HashGridClampsRadiiAboveItsMaxRadius) {
    Device& device = test::testDevice();
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclPhoton> map(2000);
    for (auto& p : map) p = makePhoton(Vec3(u(rng), u(rng), 0.0f), Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(1.0f));
    std::vector<PclEstimateQuery> wide(300), capped;
    for (auto& q : wide) q = makeQuery(Vec3(u(rng), u(rng), 0.0f), Vec3(0, 0, 1), 0.3f, 100);
    capped = wide;
    for (auto& q : capped) q.maxRadius2 = 0.05f * 0.05f;
    const PhotonMapOnDevice grid(device, map, KnnStructure::HashGrid, 0.05f);
    cl::Buffer qb = device.upload(wide);
    cl::Buffer out = device.allocate<PclEstimate>(wide.size());
    estimateBuffers(device, grid, qb, wide.size(), 100, {}, nullptr, out);
    const std::vector<PclEstimate> got = device.download<PclEstimate>(out, wide.size());
    const std::vector<PclEstimate> want = referenceEstimate(map, capped, {}, nullptr);
    size_t clampedQueries = 0;
    for (size_t i = 0; i < wide.size(); ++i) {
        ASSERT_EQ(got[i].found, want[i].found) << i;
        ASSERT_EQ(got[i].radius2, want[i].radius2) << i;
        clampedQueries += want[i].found < 100;
    }
    EXPECT_GT(clampedQueries, wide.size() / 2);  // r_max, not k, limited most of them
}

TEST(Estimate, PhotonsAtTheQueryPointGiveZeroNotNaN) {
    Device& device = test::testDevice();
    std::vector<PclPhoton> map(10, makePhoton(Vec3(0.5f), Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(1.0f)));
    std::vector<PclEstimateQuery> qs = {makeQuery(Vec3(0.5f), Vec3(0, 0, 1), 0.1f, 5),
                                        makeQuery(Vec3(3.0f), Vec3(0, 0, 1), 0.1f, 5)};
    for (KnnStructure s : kStructures) {
        EstimateSettings settings;
        settings.structure = s;
        const EstimateResult r = estimateOnDevice(device, map, qs, settings, nullptr);
        EXPECT_EQ(r.values[0].found, 5u);  // r² = 0: nothing to divide by
        EXPECT_EQ(r.values[0].r, 0.0f);
        EXPECT_EQ(r.values[0].used, 0u);
        EXPECT_EQ(r.values[1].found, 0u);
        EXPECT_EQ(r.values[1].r, 0.0f);
        EXPECT_TRUE(finite(r.values[0]) && finite(r.values[1]));
    }
    const std::vector<PclEstimate> twin = referenceEstimate(map, qs, {}, nullptr);
    EXPECT_EQ(twin[0].r, 0.0f);
    EXPECT_EQ(twin[1].r, 0.0f);
}

TEST(Estimate, MatchesTwinOnCornellBoxSurfacePoints) {
    const std::filesystem::path path = std::filesystem::path(PHOTONCL_SOURCE_DIR) / "scenes" / "cornell-box.json";
    ASSERT_TRUE(std::filesystem::exists(path)) << path;
    EstimateCheckOptions o;
    o.photons = 20000;
    o.surfaceQueries = 1500;
    o.randomQueries = 500;
    const EstimateCheckReport report = checkEstimate(test::testDevice(), loadScene(path.string()), o);
    std::printf("%s", report.table().c_str());
    EXPECT_TRUE(report.passed()) << report.table();
    double maxErr = 0.0;
    size_t surfaceNonzero = 0;
    for (const auto& r : report.rows) {
        maxErr = std::max(maxErr, r.maxRelError);
        if (r.map == "global" && r.queries == "surface") surfaceNonzero = std::max(surfaceNonzero, r.nonzero);
    }
    EXPECT_GT(surfaceNonzero, size_t(o.surfaceQueries) / 2);
    std::printf("[figure] estimate vs twin, cornell-box (%zu rows): max rel diff %.2e\n", report.rows.size(), maxErr);
}

// ---- b. Uniform density ---------------------------------------------------------------------
// n photons of power Φ uniform in the unit square (λ = n per m²) on z = 0, normals +z, arriving
// from above; queries at interior points, k nearest. With X = λπr_k² ~ Gamma(k, 1):
// E[1/(πr_k²)] = λ/(k−1) and E[1/(πr_k²)²] = λ²/((k−1)(k−2)). Given r_k the k−1 inner photons
// are uniform in the disc, independent of r_k, and the k-th sits at u = 1, so with S =
// Σ_{k−1} w(u_i) + w(1): E[S] = (k−1)m + w(1) (m = mean of w over the disc = norm),
// Var[S] = (k−1)v (v = variance of w over the disc), and the estimate Φ S / (norm π r_k²) has
//   E = λΦ (1 + w(1) / (norm (k−1)))     (box: λΦ k/(k−1); Epanechnikov: λΦ; Gaussian: close)
//   relVar = [(k−1)v + E[S]²] / E[S]² · (k−1)/(k−2) − 1     (box: exactly 1/(k−2)).
struct Expectation {
    double mean, relSpread;
};
Expectation uniformExpectation(EstimateFilter f, double coneK, double lambdaPhi, int k) {
    const double m = discMean([&](double u) { return weight(f, coneK, u); });
    const double m2 = discMean([&](double u) { return weight(f, coneK, u) * weight(f, coneK, u); });
    const double v = m2 - m * m, w1 = weight(f, coneK, 1.0);
    const double es = (k - 1) * m + w1;
    const double relVar = ((k - 1) * v + es * es) / (es * es) * double(k - 1) / double(k - 2) - 1.0;
    return {lambdaPhi * (1.0 + w1 / (m * (k - 1))), std::sqrt(relVar)};
}

struct Moments {
    double mean = 0.0, relSpread = 0.0;
};
Moments moments(const std::vector<PclEstimate>& e, size_t first, size_t count) {
    double s = 0.0, s2 = 0.0;
    for (size_t i = first; i < first + count; ++i) s += e[i].r;
    const double mean = s / count;
    for (size_t i = first; i < first + count; ++i) s2 += (e[i].r - mean) * (e[i].r - mean);
    return {mean, std::sqrt(s2 / (count - 1)) / mean};
}

TEST(Estimate, UniformDensityMeanAndSpreadMatchTheAnalyticExpectation) {
    Device& device = test::testDevice();
    const size_t n = 1000000;
    const int k = 50;
    std::mt19937 rng(2024);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const float phiIn = 1.0f / float(n);
    std::vector<PclPhoton> map(n);
    for (auto& p : map) p = makePhoton(Vec3(u(rng), u(rng), 0.0f), Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(phiIn));
    float phi, unused1, unused2;
    photon_rgbe_decode(map[0].rgbe, &phi, &unused1, &unused2);  // the power as stored
    const double lambdaPhi = double(n) * phi;
    std::vector<PclEstimateQuery> qs(10000);
    for (auto& q : qs) q = makeQuery(Vec3(0.05f + 0.9f * u(rng), 0.05f + 0.9f * u(rng), 0.0f), Vec3(0, 0, 1), 0.03f, k);
    const PhotonMapOnDevice built(device, map, KnnStructure::KdTree, 0.03f);
    std::printf("[figure] uniform plane: %zu photons, %zu queries, k = %d; kd-tree build %.2f s\n", n, qs.size(), k,
                built.buildSeconds());
    // The twin on the first 200 queries (brute force over the 1M photons): the same estimates.
    const std::vector<PclEstimateQuery> twinQs(qs.begin(), qs.begin() + 200);
    const ReferenceKnn brute = referenceKnnBruteForce(map, estimateKnnQueries(twinQs));
    for (EstimateFilter f : allEstimateFilters()) {
        EstimateSettings settings;
        settings.filter = f;
        const EstimateResult r = estimateOnDevice(device, built, qs, settings, nullptr);
        for (const PclEstimate& e : r.values) ASSERT_EQ(e.used, uint32_t(k));
        double twinErr = 0.0;
        expectSame(referenceEstimateWithKnn(map, twinQs, brute, settings, nullptr),
                   std::vector<PclEstimate>(r.values.begin(), r.values.begin() + twinQs.size()), estimateFilterName(f),
                   &twinErr);
        std::printf("[figure] uniform %-12s twin vs device on 200 queries: max rel diff %.2e\n", estimateFilterName(f),
                    twinErr);
        const Moments got = moments(r.values, 0, r.values.size());
        const Expectation want = uniformExpectation(f, settings.coneK, lambdaPhi, k);
        std::printf("[figure] uniform %-12s mean/λΦ %.5f (expected %.5f, rel err %+.3f %%), rel spread %.4f "
                    "(expected %.4f, ratio %.3f; 1/sqrt(k-2) = %.4f), %.3f s device\n",
                    estimateFilterName(f), got.mean / lambdaPhi, want.mean / lambdaPhi,
                    100.0 * (got.mean / want.mean - 1.0), got.relSpread, want.relSpread, got.relSpread / want.relSpread,
                    1.0 / std::sqrt(k - 2.0), r.timing.knnSeconds + r.timing.estimateSeconds);
        EXPECT_NEAR(got.mean / want.mean, 1.0, 0.005) << estimateFilterName(f);
        EXPECT_NEAR(got.relSpread / want.relSpread, 1.0, 0.2) << estimateFilterName(f);
    }
}

// ---- c. Boundary bias -----------------------------------------------------------------------
// 8×8 squares of side 0.1, 0.03 apart (more than r_max = 0.02, so no square sees another), at
// the same photon density as above; per square 4 corners, 3 points on each edge and 4 interior
// points (all ≥ 0.02 from the edges). With k photons found in a half (quarter) disc, r² doubles
// (quadruples) and the estimate halves (quarters) for every filter, as the weights' mean over a
// half or quarter disc equals theirs over the disc.
TEST(Estimate, EdgeAndCornerReadHalfAndQuarterOfTheInterior) {
    Device& device = test::testDevice();
    const int tiles = 8, k = 50;
    const float side = 0.1f, pitch = 0.13f, rMax = 0.02f;
    const size_t perTile = 10000;  // density 10^6 per m², as above
    std::mt19937 rng(77);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclPhoton> map;
    map.reserve(perTile * tiles * tiles);
    std::vector<PclEstimateQuery> interior, edge, corner;
    const Vec3 up(0, 0, 1);
    for (int ty = 0; ty < tiles; ++ty)
        for (int tx = 0; tx < tiles; ++tx) {
            const float x0 = tx * pitch, y0 = ty * pitch;
            for (size_t i = 0; i < perTile; ++i)
                map.push_back(makePhoton(Vec3(x0 + side * u(rng), y0 + side * u(rng), 0.0f), up, up, Vec3(1e-6f)));
            for (float cx : {0.0f, side})
                for (float cy : {0.0f, side}) corner.push_back(makeQuery(Vec3(x0 + cx, y0 + cy, 0), up, rMax, k));
            for (float t : {0.03f, 0.05f, 0.07f}) {
                edge.push_back(makeQuery(Vec3(x0 + t, y0, 0), up, rMax, k));
                edge.push_back(makeQuery(Vec3(x0 + t, y0 + side, 0), up, rMax, k));
                edge.push_back(makeQuery(Vec3(x0, y0 + t, 0), up, rMax, k));
                edge.push_back(makeQuery(Vec3(x0 + side, y0 + t, 0), up, rMax, k));
            }
            for (float a : {0.035f, 0.065f})
                for (float b : {0.035f, 0.065f}) interior.push_back(makeQuery(Vec3(x0 + a, y0 + b, 0), up, rMax, k));
        }
    std::vector<PclEstimateQuery> qs = interior;
    qs.insert(qs.end(), edge.begin(), edge.end());
    qs.insert(qs.end(), corner.begin(), corner.end());
    const PhotonMapOnDevice built(device, map, KnnStructure::HashGrid, rMax);
    for (EstimateFilter f : allEstimateFilters()) {
        EstimateSettings settings;
        settings.filter = f;
        const EstimateResult r = estimateOnDevice(device, built, qs, settings, nullptr);
        for (const PclEstimate& e : r.values) ASSERT_EQ(e.found, uint32_t(k)) << "r_max too small for k";
        const double in = moments(r.values, 0, interior.size()).mean;
        const double ed = moments(r.values, interior.size(), edge.size()).mean;
        const double co = moments(r.values, interior.size() + edge.size(), corner.size()).mean;
        std::printf("[figure] boundary %-12s edge/interior %.4f (%zu points), corner/interior %.4f (%zu points)\n",
                    estimateFilterName(f), ed / in, edge.size(), co / in, corner.size());
        EXPECT_NEAR(ed / in, 0.5, 0.02) << estimateFilterName(f);
        EXPECT_NEAR(co / in, 0.25, 0.02) << estimateFilterName(f);
    }
}

// ---- d. Light leaking through a thin wall ---------------------------------------------------
// Two closed rooms [−1, −t/2] and [t/2, 1] (× [0, 1] × [0, 1]) of diffuse quads, sharing a wall
// of thickness t = 0.1 r_max; a point light in room A only. Room B's floor and ceiling are
// coplanar with A's, so A's floor photons pass B's normal tests: only the visibility test stops
// them. The shared wall's B face (normal +x) sees A's photons only on A's wall face (normal −x)
// and floor/ceiling (normals ±y): the normal test rejects them all.
// `count` points on the face of room [lo, hi] at coordinate `axis` = lo or hi (side), inward
// normal; half of them within `near` of x = nearX when the face touches it.
void facePoints(Vec3 lo, Vec3 hi, int axis, bool high, uint32_t count, float nearX, float near, float rMax, uint32_t k,
                std::mt19937& rng, std::vector<PclEstimateQuery>& out) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (uint32_t i = 0; i < count; ++i) {
        Vec3 p, n(0.0f);
        for (int a = 0; a < 3; ++a) p[a] = lo[a] + u(rng) * (hi[a] - lo[a]);
        p[axis] = high ? hi[axis] : lo[axis];
        n[axis] = high ? -1.0f : 1.0f;
        if (axis != 0 && i % 2 == 0) p.x = nearX <= lo.x ? lo.x + u(rng) * near : hi.x - u(rng) * near;
        out.push_back(makeQuery(p, n, rMax, k));
    }
}

TEST(Estimate, NoLightLeaksThroughAThinWallWithVisibility) {
    Device& device = test::testDevice();
    const float rMax = 0.1f, t = 0.1f * rMax;
    const uint32_t k = 50;
    Scene s;
    const int white = test::addMaterial(s, Vec3(0.7f));
    const Vec3 aLo(-1.0f, 0.0f, 0.0f), aHi(-t / 2, 1.0f, 1.0f), bLo(t / 2, 0.0f, 0.0f), bHi(1.0f, 1.0f, 1.0f);
    test::addRoom(s, aLo, aHi, white);
    test::addRoom(s, bLo, bHi, white);
    s.lights.push_back(test::pointLight(Vec3(-0.3f, 0.5f, 0.5f), Vec3(10.0f)));
    test::BuiltScene b = test::build(s);
    PhotonPassOptions po;
    po.globalPhotons = 100000;
    po.buildCaustic = false;
    po.seed = 3;
    const PhotonMaps maps = runPhotonPass(device, b.geometry, b.buffers, po);
    ASSERT_GT(maps.global.size(), 50000u);
    for (const PclPhoton& p : maps.global) ASSERT_LT(p.x, 0.0f) << "a photon reached room B";

    // Room B: every face, half the points of the floor, ceiling and side walls within r_max of
    // the shared wall; the shared wall's B face (x = t/2) on its own.
    std::mt19937 rng(9);
    std::vector<PclEstimateQuery> roomB, wallB, roomA;
    for (int axis : {1, 2})
        for (bool high : {false, true}) facePoints(bLo, bHi, axis, high, 400, bLo.x, rMax, rMax, k, rng, roomB);
    facePoints(bLo, bHi, 0, true, 200, bLo.x, rMax, rMax, k, rng, roomB);  // the far wall
    facePoints(bLo, bHi, 0, false, 400, bLo.x, rMax, rMax, k, rng, wallB);
    for (int axis : {0, 1, 2})
        for (bool high : {false, true}) facePoints(aLo, aHi, axis, high, 100, aHi.x, rMax, rMax, k, rng, roomA);
    std::vector<PclEstimateQuery> qs = roomB;
    qs.insert(qs.end(), wallB.begin(), wallB.end());
    qs.insert(qs.end(), roomA.begin(), roomA.end());

    const DeviceScene deviceScene(device, b.geometry, b.buffers);
    for (bool visibility : {true, false}) {
        EstimateSettings settings;
        settings.visibility = visibility;
        settings.rayEpsilon = b.buffers.rayEpsilon;
        for (KnnStructure st : kStructures) {
            settings.structure = st;
            const EstimateResult r = estimateOnDevice(device, maps.global, qs, settings, &deviceScene);
            double leakMax = 0.0, leakSum = 0.0, aMin = INFINITY, aMean = 0.0;
            size_t leaking = 0, leakingNear = 0, foundB = 0;
            for (size_t i = 0; i < roomB.size(); ++i) {
                const PclEstimate& e = r.values[i];
                foundB += e.found > 0;
                if (e.r != 0.0f || e.g != 0.0f || e.b != 0.0f) {
                    ++leaking;
                    leakingNear += roomB[i].x < bLo.x + rMax;
                    leakMax = std::max(leakMax, double(e.r));
                    leakSum += e.r;
                }
            }
            size_t wallNonzero = 0;
            for (size_t i = 0; i < wallB.size(); ++i) {
                const PclEstimate& e = r.values[roomB.size() + i];
                wallNonzero += e.r != 0.0f || e.g != 0.0f || e.b != 0.0f;
            }
            size_t aZero = 0;
            for (size_t i = 0; i < roomA.size(); ++i) {
                const PclEstimate& e = r.values[roomB.size() + wallB.size() + i];
                ASSERT_TRUE(finite(e));
                aMin = std::min(aMin, double(e.r));
                aMean += e.r / roomA.size();
                aZero += e.r == 0.0f;
            }
            std::printf("[figure] leak %-9s visibility %-3s: room B %zu/%zu points nonzero (%zu within r_max of the "
                        "wall; %zu find photons), max %.4g W/m², mean over leaking %.4g; B wall face %zu/%zu nonzero; "
                        "room A mean %.4g, %zu/%zu zero\n",
                        knnStructureName(st), visibility ? "on" : "off", leaking, roomB.size(), leakingNear, foundB,
                        leakMax, leaking ? leakSum / leaking : 0.0, wallNonzero, wallB.size(), aMean, aZero,
                        roomA.size());
            EXPECT_EQ(wallNonzero, 0u) << "the normal test alone must keep the shared wall's B face dark";
            EXPECT_GT(foundB, roomB.size() / 4) << "the test needs B points that find A's photons";
            EXPECT_GT(aMean, 0.0);
            EXPECT_LT(aZero, roomA.size() / 20);
            if (visibility) {
                EXPECT_EQ(leaking, 0u) << "light leaked into room B with the visibility test on";
            } else EXPECT_GT(leaking, 0u) << "expected leaks through the coplanar floor/ceiling without visibility";
        }
    }
}

// The visibility lift h = rayEpsilon + 0.25 r: on a convex curved surface the chord between two
// points r apart dips r²/(8R) below it (the sagitta), so segments lifted by rayEpsilon alone
// would hit the surface itself. 20 000 photons uniform on a unit sphere (k = 50, so r ≈ 0.1 and
// chords of up to r dip ≈ 1.2e-3, above the scene's rayEpsilon 3.5e-4 and far below 0.25 r): the
// visibility test rejects none of them (with the lift at 0 it rejected 72 % of them).
TEST(Estimate, VisibilityLiftKeepsConvexSurfacesFromOccludingThemselves) {
    Device& device = test::testDevice();
    Scene s;
    Sphere sp;
    sp.radius = 1.0f;
    sp.material = test::addMaterial(s, Vec3(0.5f));
    s.spheres.push_back(sp);
    test::BuiltScene b = test::build(s);
    std::mt19937 rng(12);
    std::normal_distribution<float> g(0.0f, 1.0f);
    auto onSphere = [&] {
        Vec3 n;
        do n = Vec3(g(rng), g(rng), g(rng));
        while (length(n) < 1e-3f);
        return normalize(n);
    };
    std::vector<PclPhoton> map(20000);
    for (auto& p : map) {
        const Vec3 n = onSphere();
        p = makePhoton(n, normalize(n + onSphere() * 0.5f), n, Vec3(1e-5f));
    }
    std::vector<PclEstimateQuery> qs(2000);
    for (auto& q : qs) {
        const Vec3 n = onSphere();
        q = makeQuery(n, n, 0.3f, 50);
    }
    const DeviceScene deviceScene(device, b.geometry, b.buffers);
    const PhotonMapOnDevice built(device, map, KnnStructure::KdTree, 0.3f);
    EstimateSettings settings;
    settings.rayEpsilon = b.buffers.rayEpsilon;
    const EstimateResult off = estimateOnDevice(device, built, qs, settings, &deviceScene);
    settings.visibility = true;
    const EstimateResult on = estimateOnDevice(device, built, qs, settings, &deviceScene);
    size_t usedOff = 0, usedOn = 0;
    for (size_t i = 0; i < qs.size(); ++i) {
        usedOff += off.values[i].used;
        usedOn += on.values[i].used;
        EXPECT_EQ(on.values[i].r, off.values[i].r) << i;
    }
    std::printf("[figure] unit sphere, k = 50: photons used with visibility %zu, without %zu\n", usedOn, usedOff);
    EXPECT_GT(usedOff, qs.size() * 40);
    // The twin agrees on the visibility-tested estimates.
    const std::vector<PclEstimateQuery> few(qs.begin(), qs.begin() + 200);
    double maxErr = 0.0;
    expectSame(referenceEstimate(map, few, settings, &b.geometry),
               std::vector<PclEstimate>(on.values.begin(), on.values.begin() + few.size()), "sphere", &maxErr);
}

}  // namespace
}  // namespace pcl
