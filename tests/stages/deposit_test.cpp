// deposit_scan / deposit_scatter (kernels/deposit.cl) and the whole photon pass's ordering:
// the scan equals std::exclusive_scan on random counts at every size that exercises the
// recursion; the scatter places slot k of path i at offset[i] + k; a map that would overflow
// grows (and says so) instead of dropping records; and the pass is deterministic: the same
// bytes run after run and whatever the batch size.
#include <gtest/gtest.h>

#include <cstring>
#include <numeric>
#include <random>

#include "check/on_device.h"
#include "device_fixture.h"
#include "photon_test_scenes.h"
#include "pipeline/deposit.h"
#include "pipeline/emit.h"
#include "pipeline/photon_pass.h"
#include "pipeline/trace_photons.h"

namespace pcl {
namespace {

TEST(Deposit, ScanMatchesStdExclusiveScanOnRandomCounts) {
    std::mt19937 rng(42);
    for (size_t n : {size_t(1), size_t(255), size_t(256), size_t(257), size_t(65536 + 3), size_t(300001)}) {
        std::uniform_int_distribution<uint32_t> count(0, 64);
        std::vector<uint32_t> values(n);
        for (uint32_t& v : values) v = count(rng);
        std::vector<uint32_t> want(n);
        std::exclusive_scan(values.begin(), values.end(), want.begin(), 0u);
        std::vector<uint32_t> got = exclusiveScanOnDevice(test::testDevice(), values);
        ASSERT_EQ(got, want) << "n = " << n;
    }
}

// Random counts and slots with recognisable contents: slot k of path i holds (i, k).
struct RandomBatch {
    std::vector<uint32_t> counts;
    std::vector<PclPhoton> slots;
    uint32_t slotsPerPath = 5;
};

RandomBatch randomBatch(size_t paths, uint32_t seed) {
    RandomBatch b;
    std::mt19937 rng(seed);
    std::uniform_int_distribution<uint32_t> count(0, b.slotsPerPath);
    b.counts.resize(paths);
    b.slots.resize(paths * b.slotsPerPath);
    for (size_t i = 0; i < paths; ++i) {
        b.counts[i] = count(rng);
        for (uint32_t k = 0; k < b.slotsPerPath; ++k) {
            PclPhoton& p = b.slots[i * b.slotsPerPath + k];
            p.x = float(i);
            p.y = float(k);
            p.z = k < b.counts[i] ? 1.0f : -1.0f;  // -1: garbage past the count
            p.rgbe = uint32_t(i * 7 + k);
            p.packed = k;
        }
    }
    return b;
}

std::vector<PclPhoton> expectedOrder(const RandomBatch& b) {
    std::vector<PclPhoton> out;
    for (size_t i = 0; i < b.counts.size(); ++i)
        for (uint32_t k = 0; k < b.counts[i]; ++k) out.push_back(b.slots[i * b.slotsPerPath + k]);
    return out;
}

TEST(Deposit, ScatterAppendsInPathThenHitOrder) {
    RandomBatch b = randomBatch(70001, 1);
    std::vector<PclPhoton> want = expectedOrder(b);
    uint32_t growths = 99;
    std::vector<PclPhoton> got = depositOnDevice(test::testDevice(), b.counts, b.slots, b.slotsPerPath, 0, &growths);
    ASSERT_EQ(got.size(), want.size());
    EXPECT_EQ(std::memcmp(got.data(), want.data(), want.size() * sizeof(PclPhoton)), 0);
    EXPECT_EQ(growths, 0u);
    for (const PclPhoton& p : got) ASSERT_EQ(p.z, 1.0f) << "a slot past its path's count was copied";
}

TEST(Deposit, AMapThatWouldOverflowGrowsAndKeepsEveryRecord) {
    Device& dev = test::testDevice();
    RandomBatch a = randomBatch(5000, 2), b = randomBatch(7000, 3);
    DevicePhotonMap map = makeDevicePhotonMap(dev, 100);
    cl::Buffer ca = dev.upload(a.counts), sa = dev.upload(slotMajor(a.slots, 5000, a.slotsPerPath));
    cl::Buffer cb = dev.upload(b.counts), sb = dev.upload(slotMajor(b.slots, 7000, b.slotsPerPath));
    size_t na = depositPhotons(dev, ca, sa, 5000, map);
    EXPECT_EQ(map.growths, 1u);
    size_t nb = depositPhotons(dev, cb, sb, 7000, map);
    EXPECT_GE(map.growths, 2u);
    std::vector<PclPhoton> want = expectedOrder(a), wantB = expectedOrder(b);
    ASSERT_EQ(na, want.size());
    ASSERT_EQ(nb, wantB.size());
    want.insert(want.end(), wantB.begin(), wantB.end());
    ASSERT_EQ(map.count, want.size());
    EXPECT_GE(map.capacity, map.count);
    std::vector<PclPhoton> got = dev.download<PclPhoton>(map.photons, map.count);
    EXPECT_EQ(std::memcmp(got.data(), want.data(), want.size() * sizeof(PclPhoton)), 0);
}

test::BuiltScene cornellLike() {
    Scene s;
    int white = test::addMaterial(s, Vec3(0.7f));
    int red = test::addMaterial(s, Vec3(0.6f, 0.1f, 0.1f));
    int mirror = test::addMaterial(s, Vec3(0.0f), Vec3(0.9f), SpecularKind::Mirror);
    int glass = test::addMaterial(s, Vec3(0.0f), Vec3(1.0f), SpecularKind::Dielectric, 0.0f, 1.5f);
    int glossy = test::addMaterial(s, Vec3(0.3f), Vec3(0.5f), SpecularKind::Glossy, 40.0f);
    s.meshes.push_back(test::closedBox(1.0f, white));
    TriangleMesh wall;
    wall.material = red;
    test::addQuad(wall, Vec3(-0.99f, -1, -1), Vec3(-0.99f, 1, -1), Vec3(-0.99f, 1, 1), Vec3(-0.99f, -1, 1));
    s.meshes.push_back(wall);
    for (int k = 0; k < 3; ++k) {
        Sphere sp;
        sp.centre = Vec3(-0.5f + 0.5f * k, -0.7f, 0.1f * k);
        sp.radius = 0.25f;
        sp.material = k == 0 ? mirror : k == 1 ? glass : glossy;
        s.spheres.push_back(sp);
    }
    test::addAreaLight(s, 0.98f, 0.2f, Vec3(10.0f));
    return test::build(s);
}

PhotonMaps pass(const test::BuiltScene& b, uint32_t batch, size_t capacity = 0) {
    PhotonPassOptions o;
    o.globalPhotons = 30000;
    o.causticPhotons = 30000;
    o.batchSize = batch;
    o.initialCapacity = capacity;
    o.seed = 77;
    return runPhotonPass(test::testDevice(), b.geometry, b.buffers, o);
}

bool sameBytes(const std::vector<PclPhoton>& a, const std::vector<PclPhoton>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(PclPhoton)) == 0;
}

TEST(Deposit, PhotonMapsAreByteIdenticalRunToRunAndAcrossBatchSizes) {
    test::BuiltScene b = cornellLike();
    test::markAllProjectionCells(b.buffers);
    PhotonMaps one = pass(b, 0);
    std::printf("%s", one.stats.summary().c_str());
    ASSERT_GT(one.global.size(), 30000u);
    ASSERT_GT(one.caustic.size(), 100u);
    PhotonMaps again = pass(b, 0);
    EXPECT_TRUE(sameBytes(one.global, again.global));
    EXPECT_TRUE(sameBytes(one.caustic, again.caustic));
    PhotonMaps small = pass(b, 777);
    EXPECT_GT(small.stats.global.batches, 30u);
    EXPECT_TRUE(sameBytes(one.global, small.global));
    EXPECT_TRUE(sameBytes(one.caustic, small.caustic));
    // A tiny first buffer: grown, reported, nothing lost or reordered.
    PhotonMaps grown = pass(b, 4096, 64);
    EXPECT_GT(grown.stats.global.growths, 0u);
    EXPECT_GT(grown.stats.caustic.growths, 0u);
    EXPECT_TRUE(sameBytes(one.global, grown.global));
    EXPECT_TRUE(sameBytes(one.caustic, grown.caustic));
    // Every kind of end shows up in this scene, and the counts add up.
    const PhotonPassKindStats& g = one.stats.global;
    EXPECT_EQ(g.escaped + g.absorbed + g.maxDepth, g.emitted);
    const PhotonPassKindStats& c = one.stats.caustic;
    EXPECT_EQ(c.escaped + c.absorbed + c.maxDepth + c.stored, c.emitted);
    // STORED counts caustic paths that ended where they deposited; the glossy sphere (mixed)
    // lets some deposit and go on, so records outnumber them.
    EXPECT_GT(c.stored, 0u);
    EXPECT_LT(c.stored, one.caustic.size());
}

// The per-stage entry points a check calls (emitOnDevice → tracePhotonsOnDevice →
// depositOnDevice) give the very map the pipeline builds.
TEST(Deposit, StageByStageEqualsThePipeline) {
    test::BuiltScene b = cornellLike();
    test::markAllProjectionCells(b.buffers);
    PhotonMaps whole = pass(b, 0);
    for (uint32_t kind : {PCL_PASS_GLOBAL, PCL_PASS_CAUSTIC}) {
        std::vector<uint32_t> first = lightFirstPhoton(b.buffers, 30000, kind);
        PclPhotonParams p = makePhotonParams(b.geometry, b.buffers, kind, photonPassSeed(77, 0), 64, 0, first.back());
        auto rays = emitOnDevice(test::testDevice(), b.geometry, b.buffers, first, p);
        PhotonTraceResult t = tracePhotonsOnDevice(test::testDevice(), b.geometry, b.buffers, rays, p);
        std::vector<PclPhoton> map = depositOnDevice(test::testDevice(), t.counts, t.slots, t.slotsPerPath);
        EXPECT_TRUE(sameBytes(map, kind == PCL_PASS_GLOBAL ? whole.global : whole.caustic)) << "pass " << kind;
    }
}

}  // namespace
}  // namespace pcl
