// Precomputed irradiance (kernels/precomputed_irradiance.cl, pipeline/precomputed_irradiance)
// against its twin and against the full estimate, through check/precomputed_irradiance (which
// states the tolerances): on a uniformly lit plane and on cornell-box.json's real global map the
// selection matches the twin exactly, the stored irradiance within 1e-5 relative and the covers
// bit for bit, every lookup chooses the brute force's point and returns its value bit for bit, a
// lookup at a stored point returns that point, and the mean lookup over ≥ 10 000 surface points
// is within 1 % of the full estimate's mean at the same points. A thin wall (two faces back to
// back) never reads the other face; a point answers only inside its cover; the stage's buffer
// list for the memory plan matches its allocations. Speed-ups are printed as "[figure]" lines,
// never asserted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>

#include "check/on_device.h"
#include "check/precomputed_irradiance.h"
#include "device_fixture.h"
#include "pipeline/precomputed_irradiance.h"
#include "reference/precomputed_irradiance.h"
#include "reference/trace_photons.h"
#include "scene/load_scene.h"

namespace pcl {
namespace {

constexpr double kPi = 3.14159265358979323846;

// n photons uniform on the square [0, 1]² of the plane z = z0, facing `nz` (±1), each carrying
// `power` W in every channel (RGBE-exact for powers of two).
std::vector<PclPhoton> planePhotons(size_t n, float z0, float nz, float power, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclPhoton> map(n);
    for (PclPhoton& p : map) {
        p = PclPhoton{};
        p.x = u(rng), p.y = u(rng), p.z = z0;
        p.rgbe = referenceEncodeRgbe(Vec3(power));
        p.packed = referenceEncodeDirection(Vec3(0.0f, 0.0f, nz));  // arrived straight along the normal
        p.normal = referenceEncodeNormal(Vec3(0.0f, 0.0f, nz));
    }
    return map;
}

// Queries on the plane z = z0 facing nz, uniform in [m, 1 − m]² (away from the boundary bias).
std::vector<PclEstimateQuery> planeQueries(size_t n, float z0, float nz, float margin, float maxRadius, uint32_t k,
                                           uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(margin, 1.0f - margin);
    std::vector<PclEstimateQuery> qs(n);
    for (PclEstimateQuery& q : qs) {
        q = PclEstimateQuery{};
        q.x = u(rng), q.y = u(rng), q.z = z0;
        q.maxRadius2 = maxRadius * maxRadius;
        q.nx = 0.0f, q.ny = 0.0f, q.nz = nz;
        q.k = k;
    }
    return qs;
}

void printFigures(const IrradianceCheckReport& r) {
    std::printf("%s", r.table().c_str());
    std::printf("[figure] precomputed irradiance, %s: lookup mean / full-estimate mean = %.5f over %zu points, "
                "per-point RMS relative difference %.4f, RMS difference / mean %.4f\n",
                r.name.c_str(), r.meanEstimate > 0 ? r.meanLookup / r.meanEstimate : 0.0, r.accuracyQueries,
                r.rmsRelativeDifference, r.rmsDifferenceOverMean);
    std::printf("[figure] precomputed irradiance, %s: lookup %.1fx faster per query than the full estimate "
                "(k = %u, device %s)\n",
                r.name.c_str(), r.speedUp(), 50u, test::testDevice().info().name.c_str());
}

TEST(PrecomputedIrradiance, UniformlyLitPlaneMatchesTheFullEstimate) {
    const size_t n = 200000;
    const uint32_t k = 50;
    const float power = 1.0f / 1024.0f;
    const float lambda = float(n);                            // photons per unit area
    const float rMax = 2.0f * std::sqrt(k / (kPi * lambda));  // ~4k photons expected inside
    const std::vector<PclPhoton> map = planePhotons(n, 0.0f, 1.0f, power, 11);
    IrradianceCheckOptions o;
    o.k = k;
    const std::vector<PclEstimateQuery> surface = planeQueries(10000, 0.0f, 1.0f, 2 * rMax, rMax, k, 12);
    const IrradianceCheckReport r = checkPrecomputedIrradianceOnMap(test::testDevice(), map, surface, rMax, o, "plane");
    printFigures(r);
    EXPECT_TRUE(r.passed());
    EXPECT_EQ(r.points, n / 4);
    EXPECT_EQ(r.selectionMismatches, 0u);
    EXPECT_LE(r.storedMaxError, kIrradianceStoredTolerance);
    EXPECT_EQ(r.choiceMismatches, 0u);
    EXPECT_EQ(r.valueMismatches, 0u);
    EXPECT_EQ(r.exactFailures, 0u);
    EXPECT_GE(r.accuracyQueries, 10000u);
    EXPECT_LE(r.meanRelativeError(), 0.01);
    // Both read the plane's irradiance λΦ (E[k/πr²] = λk/(k−1) and the filters' own bias aside:
    // the estimate's tests bound those), so a lookup that read the wrong points would show here.
    EXPECT_NEAR(r.meanLookup / (lambda * power), 1.0, 0.05);
    EXPECT_EQ(r.lookupZeroEstimateNot, 0u);
}

TEST(PrecomputedIrradiance, CornellGlobalMapMatchesTheFullEstimate) {
    const Scene scene = loadScene(std::string(PHOTONCL_SOURCE_DIR) + "/scenes/cornell-box.json");
    IrradianceCheckOptions o;
    o.photons = 40000;
    o.surfaceQueries = 10000;
    const IrradianceCheckReport r = checkPrecomputedIrradiance(test::testDevice(), scene, o);
    printFigures(r);
    EXPECT_TRUE(r.passed());
    EXPECT_GT(r.points, 10000u);
    EXPECT_GE(r.accuracyQueries, 10000u);
    EXPECT_EQ(r.choiceMismatches, 0u);
    EXPECT_EQ(r.exactFailures, 0u);
    EXPECT_LE(r.meanRelativeError(), 0.01);
}

// Two faces back to back 0.1 r_max apart, lit differently: lookups on one face read only its
// own points, even where the other face's points are nearer.
TEST(PrecomputedIrradiance, ThinWallNeverReadsTheOtherFace) {
    const size_t n = 40000;
    const uint32_t k = 50;
    const float rMax = 2.0f * std::sqrt(k / (kPi * n));
    const float half = 0.05f * rMax;
    std::vector<PclPhoton> map = planePhotons(n, half, 1.0f, 1.0f / 256.0f, 21);          // face A: +z, dim
    const std::vector<PclPhoton> back = planePhotons(n, -half, -1.0f, 1.0f / 16.0f, 22);  // face B: −z, bright
    map.insert(map.end(), back.begin(), back.end());
    Device& device = test::testDevice();
    PrecomputedIrradianceOptions po;
    po.k = k;
    po.maxRadius = rMax;
    const DeviceIrradianceMap irr = precomputeIrradiance(device, map, po, nullptr);
    const std::vector<PclIrradiancePoint> points = downloadIrradiancePoints(device, irr);
    const std::vector<float> cover = downloadIrradianceCover(device, irr);
    ASSERT_EQ(points.size(), 2 * n / 4);

    for (float side : {1.0f, -1.0f}) {
        // Queries on the face itself and on the other face's plane (nearer the other's points).
        for (float z : {side * half, -side * half}) {
            const std::vector<PclEstimateQuery> qs = planeQueries(5000, z, side, 2 * rMax, rMax, k, 23);
            const IrradianceLookupResult r = lookupIrradianceOnDevice(device, irr, qs);
            size_t wrongFace = 0, empty = 0;
            double sum = 0.0;
            for (size_t q = 0; q < qs.size(); ++q) {
                if (r.chosen[q] == PCL_NO_HIT) {
                    ++empty;
                    continue;
                }
                wrongFace += side > 0 ? r.chosen[q] >= n : r.chosen[q] < n;
                sum += r.irradiance[4 * q];
            }
            const double expected = (side > 0 ? 1.0 / 256.0 : 1.0 / 16.0) * n;
            const double mean = sum / std::max<size_t>(qs.size() - empty, 1);
            std::printf("[figure] thin wall, face %+g, queries at z = %+g: %zu wrong-face points, %zu empty, mean "
                        "lookup / own-face irradiance = %.4f\n",
                        side, z, wrongFace, empty, mean / expected);
            EXPECT_EQ(wrongFace, 0u);
            EXPECT_EQ(empty, 0u);
            EXPECT_NEAR(mean / expected, 1.0, 0.05);  // a leak of the other face (16× brighter) would show
            const ReferenceIrradianceLookup twin = referenceLookupIrradiance(points, cover, qs, irr.minNormalCos);
            EXPECT_EQ(twin.chosen, r.chosen);
        }
    }
}

TEST(PrecomputedIrradiance, EmptyAndSinglePointMaps) {
    Device& device = test::testDevice();
    const DeviceIrradianceMap none = uploadIrradiancePoints(device, {}, 0.9f);
    PclEstimateQuery q{};
    q.maxRadius2 = 1.0f;
    q.nz = 1.0f;
    IrradianceLookupResult r = lookupIrradianceOnDevice(device, none, {q});
    EXPECT_EQ(r.chosen[0], PCL_NO_HIT);
    EXPECT_EQ(r.irradiance, std::vector<float>(4, 0.0f));

    PclIrradiancePoint p{};
    p.x = 0.5f, p.normal = referenceEncodeNormal(Vec3(0.0f, 0.0f, 1.0f));
    p.r = 1.0f, p.g = 2.0f, p.b = 3.0f;
    p.photon = 8;
    const DeviceIrradianceMap one = uploadIrradiancePoints(device, {p}, 0.9f);
    r = lookupIrradianceOnDevice(device, one, {q});
    EXPECT_EQ(r.chosen[0], 8u);
    EXPECT_EQ(r.irradiance, (std::vector<float>{1.0f, 2.0f, 3.0f, 0.25f}));
    q.maxRadius2 = 0.2f;  // out of reach
    EXPECT_EQ(lookupIrradianceOnDevice(device, one, {q}).chosen[0], PCL_NO_HIT);
    q.maxRadius2 = 1.0f, q.nz = -1.0f;  // facing away
    EXPECT_EQ(lookupIrradianceOnDevice(device, one, {q}).chosen[0], PCL_NO_HIT);
    q.x = 0.5f, q.nz = 1.0f, q.maxRadius2 = 0.0f;  // radius 0 at the point itself
    EXPECT_EQ(lookupIrradianceOnDevice(device, one, {q}).chosen[0], 8u);
    // ... unless radius 0 marks no query (IrradianceSource's contract, the final gather's rays
    // without a diffuse hit): then none, 0, without a search.
    DeviceIrradianceLookup out;
    lookupIrradiance(device, one, device.upload(std::vector<PclEstimateQuery>{q}), 1, out, true);
    EXPECT_EQ(device.download<uint32_t>(out.chosen, 1)[0], PCL_NO_HIT);
    EXPECT_EQ(device.download<float>(out.irradiance, 4), std::vector<float>(4, 0.0f));
    q.maxRadius2 = 1e-6f;  // any positive radius searches as before
    lookupIrradiance(device, one, device.upload(std::vector<PclEstimateQuery>{q}), 1, out, true);
    EXPECT_EQ(device.download<uint32_t>(out.chosen, 1)[0], 8u);

    // Precomputation on tiny maps: nothing to select; one point and no other photon (it reads
    // 0); one point estimated from two others (the twin's value).
    PrecomputedIrradianceOptions o;
    o.maxRadius = 1.0f;
    EXPECT_EQ(precomputeIrradiance(device, std::vector<PclPhoton>{}, o, nullptr).count, 0u);
    const std::vector<PclPhoton> three = planePhotons(3, 0.0f, 1.0f, 0.5f, 31);
    for (size_t n : {size_t(1), size_t(3)}) {
        const std::vector<PclPhoton> map(three.begin(), three.begin() + n);
        const DeviceIrradianceMap m = precomputeIrradiance(device, map, o, nullptr);
        const std::vector<PclIrradiancePoint> got = downloadIrradiancePoints(device, m);
        std::vector<float> twinCover;
        const std::vector<PclIrradiancePoint> twin = referencePrecomputeIrradiance(map, o, nullptr, 0, &twinCover);
        EXPECT_EQ(downloadIrradianceCover(device, m), twinCover);
        ASSERT_EQ(got.size(), 1u);
        ASSERT_EQ(twin.size(), 1u);
        EXPECT_EQ(got[0].photon, 0u);
        EXPECT_NEAR(got[0].r, twin[0].r, 1e-5 * twin[0].r);
        if (n == 1) EXPECT_EQ(got[0].r, 0.0f);
        else EXPECT_GT(got[0].r, 0.0f);
    }
}

// The others' map through the hash grid gives the kd-tree's values bit for bit (both searches
// return the brute force's neighbours, so the estimates sum the same photons in the same order).
TEST(PrecomputedIrradiance, HashGridAndKdTreeStoreTheSameValues) {
    const size_t n = 20000;
    const std::vector<PclPhoton> map = planePhotons(n, 0.0f, 1.0f, 1.0f / 512.0f, 41);
    PrecomputedIrradianceOptions o;
    o.maxRadius = 2.0f * std::sqrt(50.0f / (float(kPi) * n));
    Device& device = test::testDevice();
    const std::vector<PclIrradiancePoint> kd =
        downloadIrradiancePoints(device, precomputeIrradiance(device, map, o, nullptr));
    o.estimate.structure = KnnStructure::HashGrid;
    const std::vector<PclIrradiancePoint> grid =
        downloadIrradiancePoints(device, precomputeIrradiance(device, map, o, nullptr));
    ASSERT_EQ(kd.size(), n / 4);
    ASSERT_EQ(grid.size(), kd.size());
    size_t differ = 0, zero = 0;
    for (size_t j = 0; j < kd.size(); ++j) {
        differ += kd[j].r != grid[j].r || kd[j].g != grid[j].g || kd[j].b != grid[j].b;
        zero += kd[j].r == 0.0f;
    }
    EXPECT_EQ(differ, 0u);
    EXPECT_EQ(zero, 0u);
}

// A point answers only queries inside the disc its estimate covered: the nearer point whose cover
// misses the query loses to a farther one that covers it, and with none covering the answer is 0.
TEST(PrecomputedIrradiance, LookupsStayInsideTheCover) {
    Device& device = test::testDevice();
    const uint32_t up = referenceEncodeNormal(Vec3(0.0f, 0.0f, 1.0f));
    PclIrradiancePoint near{}, far{};
    near.x = 0.1f, near.normal = up, near.r = near.g = near.b = 5.0f, near.photon = 0;
    far.x = -0.3f, far.normal = up, far.r = far.g = far.b = 1.0f, far.photon = 4;
    const std::vector<PclIrradiancePoint> points = {near, far};
    PclEstimateQuery q{};
    q.maxRadius2 = 1.0f, q.nz = 1.0f;
    std::vector<float> cover = {0.02f, 0.2f};  // the query is 0.1 from `near` (d² 0.01 ≤ 0.02)
    EXPECT_EQ(lookupIrradianceOnDevice(device, uploadIrradiancePoints(device, points, 0.9f, cover), {q}).chosen[0], 0u);
    cover[0] = 0.005f;  // now `near` does not reach it: `far` (d² 0.09 ≤ 0.2) answers
    IrradianceLookupResult r =
        lookupIrradianceOnDevice(device, uploadIrradiancePoints(device, points, 0.9f, cover), {q});
    EXPECT_EQ(r.chosen[0], 4u);
    EXPECT_EQ(r.irradiance[0], 1.0f);
    EXPECT_EQ(referenceLookupIrradiance(points, cover, {q}, 0.9f).chosen[0], 4u);
    cover[1] = 0.05f;  // neither does
    EXPECT_EQ(lookupIrradianceOnDevice(device, uploadIrradiancePoints(device, points, 0.9f, cover), {q}).chosen[0],
              PCL_NO_HIT);
    EXPECT_EQ(referenceLookupIrradiance(points, cover, {q}, 0.9f).chosen[0], PCL_NO_HIT);
}

// The memory plan's list of the stage's buffers is what it allocates, to the byte.
TEST(PrecomputedIrradiance, BufferListMatchesTheAllocations) {
    Device device = test::testDevice();  // a copy: the observer stays with it
    std::map<std::string, size_t> seen;
    device.setAllocationObserver([&](const std::string& what, size_t bytes) {
        if (what.rfind("precomputed irradiance:", 0) == 0 || what.rfind("query order:", 0) == 0) seen[what] += bytes;
    });
    const std::vector<PclPhoton> map = planePhotons(10001, 0.0f, 1.0f, 1.0f / 64.0f, 51);
    PrecomputedIrradianceOptions o;
    o.maxRadius = 0.05f;
    const DeviceIrradianceMap irr = precomputeIrradiance(device, map, o, nullptr);
    lookupIrradianceOnDevice(device, irr, planeQueries(777, 0.0f, 1.0f, 0.1f, 0.05f, 50, 52));
    std::map<std::string, size_t> predicted;
    for (const IrradianceBufferSize& b : precomputedIrradianceBuffers(map.size(), o.every, 777))
        predicted[b.what] += std::max<size_t>(b.count, 1) * b.elementBytes;
    EXPECT_EQ(seen, predicted);
}

// The precomputation's inputs are checked.
TEST(PrecomputedIrradiance, RejectsBadOptions) {
    PrecomputedIrradianceOptions o;
    o.maxRadius = 0.1f;
    EXPECT_NO_THROW(validatePrecomputedIrradianceOptions(o));
    o.every = 1;  // no other photons to estimate from
    EXPECT_THROW(validatePrecomputedIrradianceOptions(o), InternalError);
    o.every = 4, o.k = 0;
    EXPECT_THROW(validatePrecomputedIrradianceOptions(o), InternalError);
    o.k = 50, o.maxRadius = 0.0f;
    EXPECT_THROW(validatePrecomputedIrradianceOptions(o), InternalError);
    o.maxRadius = 0.1f, o.coverFactor = 0.0f;
    EXPECT_THROW(validatePrecomputedIrradianceOptions(o), InternalError);
    o.coverFactor = INFINITY;  // no cover limit
    EXPECT_NO_THROW(validatePrecomputedIrradianceOptions(o));
}

// The report fails on any broken criterion: the check can fail.
TEST(PrecomputedIrradiance, ReportFailsOnEachCriterion) {
    IrradianceCheckReport good;
    good.points = good.storedCompared = good.lookupCompared = good.exactCompared = good.accuracyQueries = 10;
    good.meanEstimate = 1.0, good.meanLookup = 1.005;
    ASSERT_TRUE(good.passed());
    ASSERT_TRUE(good.accurate());
    IrradianceCheckReport r = good;
    r.meanLookup = 1.02;  // the method's accuracy, reported apart from the twin criteria
    EXPECT_FALSE(r.accurate());
    EXPECT_TRUE(r.passed());
    r = good, r.selectionMismatches = 1;
    EXPECT_FALSE(r.passed());
    r = good, r.storedMaxError = 2 * kIrradianceStoredTolerance;
    EXPECT_FALSE(r.passed());
    r = good, r.coverMismatches = 1;
    EXPECT_FALSE(r.passed());
    r = good, r.choiceMismatches = 1;
    EXPECT_FALSE(r.passed());
    r = good, r.valueMismatches = 1;
    EXPECT_FALSE(r.passed());
    r = good, r.exactFailures = 1;
    EXPECT_FALSE(r.passed());
    r = good, r.accuracyQueries = 0;
    EXPECT_FALSE(r.accurate());
}

}  // namespace
}  // namespace pcl
