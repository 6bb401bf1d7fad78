// Hash grid (kernels/hashgrid.cl, pipeline/hashgrid) against its twin (reference/hashgrid):
// the same parameters, sorted hashes, photon order and cell tables, element for element, on
// random maps and degenerate ones (1M identical photons, two dense clusters, collinear, 0 and 1
// photon). The twin's tables are also checked against their definition, so a shared mistake in
// a sort or a range cannot pass unseen.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "check/on_device.h"
#include "device_fixture.h"
#include "pipeline/hashgrid.h"
#include "reference/hashgrid.h"

namespace pcl {
namespace {

PclPhoton photonAt(float x, float y, float z) {
    PclPhoton p{};
    p.x = x, p.y = y, p.z = z;
    return p;
}

std::vector<PclPhoton> uniformMap(size_t n, uint64_t seed, float lo = -1.0f, float hi = 3.0f) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(lo, hi);
    std::vector<PclPhoton> m(n);
    for (auto& p : m) p = photonAt(u(rng), u(rng), u(rng));
    return m;
}

// The twin's tables follow from their definition.
void expectWellFormed(const std::vector<PclPhoton>& map, const ReferenceHashGrid& g) {
    ASSERT_EQ(g.order.size(), map.size());
    std::vector<bool> seen(map.size(), false);
    for (size_t i = 0; i < g.order.size(); ++i) {
        ASSERT_LT(g.order[i], map.size());
        ASSERT_FALSE(seen[g.order[i]]);
        seen[g.order[i]] = true;
        const PclPhoton& p = map[g.order[i]];
        ASSERT_EQ(g.keys[i], referenceGridHash(g.params, p.x, p.y, p.z));
        if (i > 0) {
            ASSERT_TRUE(g.keys[i - 1] < g.keys[i] || (g.keys[i - 1] == g.keys[i] && g.order[i - 1] < g.order[i]));
        }
    }
    size_t covered = 0;
    for (uint32_t h = 0; h < g.params.tableSize; ++h) {
        ASSERT_LE(g.cellStart[h], g.cellEnd[h]);
        for (uint32_t s = g.cellStart[h]; s < g.cellEnd[h]; ++s) ASSERT_EQ(g.keys[s], h);
        covered += g.cellEnd[h] - g.cellStart[h];
    }
    EXPECT_EQ(covered, map.size());
}

// The points follow the order: photon order[i]'s position, its index in w's bits.
void expectPointsInOrder(const std::vector<PclPhoton>& map, const HashGridTables& dev) {
    ASSERT_EQ(dev.points.size(), dev.order.size());
    for (size_t i = 0; i < dev.order.size(); ++i) {
        const PclPhoton& p = map[dev.order[i]];
        const cl_float4& q = dev.points[i];
        uint32_t w;
        std::memcpy(&w, &q.s[3], sizeof w);
        ASSERT_TRUE(q.s[0] == p.x && q.s[1] == p.y && q.s[2] == p.z && w == dev.order[i]) << "point " << i;
    }
}

// Both builds (pipeline/hashgrid.h: Sorted, GPUs' and Bucketed, CPUs'), whatever the device.
const HashGridBuild kBuilds[] = {HashGridBuild::Sorted, HashGridBuild::Bucketed};
const char* buildName(HashGridBuild b) { return b == HashGridBuild::Sorted ? "sorted" : "bucketed"; }

void expectSameGrid(const std::vector<PclPhoton>& map, float radius) {
    const ReferenceHashGrid twin = referenceHashGrid(map, radius);
    expectWellFormed(map, twin);
    for (HashGridBuild build : kBuilds) {
        SCOPED_TRACE(buildName(build));
        const HashGridTables dev = hashGridOnDevice(test::testDevice(), map, radius, build);
        EXPECT_EQ(dev.params.ox, twin.params.ox);
        EXPECT_EQ(dev.params.oy, twin.params.oy);
        EXPECT_EQ(dev.params.oz, twin.params.oz);
        EXPECT_EQ(dev.params.cellSize, twin.params.cellSize);
        EXPECT_EQ(dev.params.invCellSize, twin.params.invCellSize);
        EXPECT_EQ(dev.params.tableSize, twin.params.tableSize);
        EXPECT_EQ(dev.params.photonCount, twin.params.photonCount);
        EXPECT_TRUE(dev.keys == twin.keys) << "sorted hashes differ";
        EXPECT_TRUE(dev.order == twin.order) << "photon order differs";
        EXPECT_TRUE(dev.cellStart == twin.cellStart) << "cellStart differs";
        EXPECT_TRUE(dev.cellEnd == twin.cellEnd) << "cellEnd differs";
        expectPointsInOrder(map, dev);
    }
}

TEST(HashGrid, RandomMapsEqualTheTwin) {
    expectSameGrid(uniformMap(100000, 1), 0.05f);
    expectSameGrid(uniformMap(4097, 2), 0.3f);    // table 8192, one past a power of two
    expectSameGrid(uniformMap(20000, 3), 1e-4f);  // far more cells than entries: many collisions
    expectSameGrid(uniformMap(5000, 4), 50.0f);   // every photon in one cell
}

TEST(HashGrid, ParamsFollowTheSpec) {
    std::vector<PclPhoton> m = {photonAt(1, 2, 3), photonAt(-1, 5, 0.5f), photonAt(2, -4, 7)};
    PclGridParams g = hashGridParams(m, 0.25f);
    EXPECT_EQ(g.ox, -1.0f);
    EXPECT_EQ(g.oy, -4.0f);
    EXPECT_EQ(g.oz, 0.5f);
    EXPECT_EQ(g.cellSize, 0.5f);
    EXPECT_EQ(g.invCellSize, 2.0f);
    EXPECT_EQ(g.tableSize, 4u);
    EXPECT_EQ(g.photonCount, 3u);
    EXPECT_THROW(hashGridParams(m, 0.0f), InternalError);
    EXPECT_THROW(hashGridParams(m, -1.0f), InternalError);
}

TEST(HashGrid, MillionIdenticalPhotons) {
    std::vector<PclPhoton> m(1000000, photonAt(0.5f, -2.0f, 3.0f));
    const ReferenceHashGrid twin = referenceHashGrid(m, 0.1f);
    const uint32_t h = twin.keys[0];
    EXPECT_EQ(twin.cellStart[h], 0u);
    EXPECT_EQ(twin.cellEnd[h], 1000000u);
    for (HashGridBuild build : kBuilds) {
        SCOPED_TRACE(buildName(build));
        const HashGridTables dev = hashGridOnDevice(test::testDevice(), m, 0.1f, build);
        EXPECT_TRUE(dev.keys == twin.keys);
        EXPECT_TRUE(dev.order == twin.order);  // identity: ties keep photon index order
        EXPECT_TRUE(dev.cellStart == twin.cellStart);
        EXPECT_TRUE(dev.cellEnd == twin.cellEnd);
        for (uint32_t i = 0; i < dev.order.size(); i += 9973) ASSERT_EQ(dev.order[i], i);
    }
}

TEST(HashGrid, ClustersCollinearAndTinyMaps) {
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<float> u(0.0f, 1e-4f);
    std::vector<PclPhoton> clusters;
    for (int i = 0; i < 30000; ++i) {
        const float c = i % 2 ? 100.0f : -50.0f;
        clusters.push_back(photonAt(c + u(rng), 2 * c + u(rng), u(rng)));
    }
    expectSameGrid(clusters, 1e-5f);
    expectSameGrid(clusters, 1.0f);
    std::vector<PclPhoton> line;
    for (int i = 0; i < 20000; ++i) line.push_back(photonAt(0.001f * i, 1.0f + 0.002f * i, -3.0f + 0.0005f * i));
    expectSameGrid(line, 0.01f);
    expectSameGrid({}, 0.1f);
    expectSameGrid({photonAt(1, 2, 3)}, 0.1f);
    const HashGridTables none = hashGridOnDevice(test::testDevice(), {}, 0.1f);
    EXPECT_EQ(none.params.tableSize, 1u);
    EXPECT_EQ(none.cellStart, std::vector<uint32_t>{0u});
    EXPECT_EQ(none.cellEnd, std::vector<uint32_t>{0u});
}

TEST(HashGrid, HugeMapTinyCellsClampCoordinates) {
    // 1e7 / 1e-6 cells per axis would overflow int: coordinates clamp to ±1e9 on both sides.
    std::vector<PclPhoton> m = uniformMap(3000, 11, -1e7f, 1e7f);
    expectSameGrid(m, 5e-7f);
}

}  // namespace
}  // namespace pcl
