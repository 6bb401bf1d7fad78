// query_order_keys / query_order_gather / query_order_scatter (kernels/query_order.cl): the
// device order is a stable sort of the host's Morton keys (queryOrderKey), the sorted queries
// are the queries in that order bit for bit, and the scatter puts sorted results back where
// their query was; queries beyond the 256-cell wrap and at non-finite places still get a key.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <random>

#include "device_fixture.h"
#include "pipeline/query_order.h"
#include "shared/types.h"

namespace pcl {
namespace {

std::vector<PclEstimateQuery> randomQueries(size_t n, float extent, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-extent, extent);
    std::vector<PclEstimateQuery> q(n);
    for (size_t i = 0; i < n; ++i) {
        q[i] = PclEstimateQuery{};
        q[i].x = u(rng), q[i].y = u(rng), q[i].z = u(rng);
        q[i].maxRadius2 = 0.01f;
        q[i].nz = 1.0f;
        q[i].k = uint32_t(i);  // a tag: which query this is
    }
    return q;
}

TEST(QueryOrder, IsAStableSortOfTheMortonKeysAndScatterInvertsIt) {
    Device& device = test::testDevice();
    for (const size_t n : {size_t(1), size_t(63), size_t(4097), size_t(100000)}) {
        std::vector<PclEstimateQuery> q = randomQueries(n, 50.0f, uint32_t(n));  // 50 / 0.1 = 500 cells: wraps
        if (n > 2) q[1].x = NAN, q[2].y = INFINITY;                              // still keyed, never UB
        const float cell = 0.1f;
        std::vector<uint32_t> expected(n);
        std::iota(expected.begin(), expected.end(), 0u);
        std::stable_sort(expected.begin(), expected.end(), [&](uint32_t a, uint32_t b) {
            return queryOrderKey(q[a].x, q[a].y, q[a].z, cell) < queryOrderKey(q[b].x, q[b].y, q[b].z, cell);
        });
        const QueryOrder o = orderQueries(device, device.upload(q, CL_MEM_READ_WRITE), n, cell);
        const std::vector<uint32_t> order = device.download<uint32_t>(o.order, n);
        ASSERT_EQ(order, expected) << n << " queries";
        const std::vector<PclEstimateQuery> sorted = device.download<PclEstimateQuery>(o.sorted, n);
        for (size_t s = 0; s < n; ++s)
            ASSERT_EQ(std::memcmp(&sorted[s], &q[order[s]], sizeof(PclEstimateQuery)), 0) << "position " << s;

        // Results of 8 floats (two float4) computed in sorted order land at their query.
        std::vector<float> sortedResults(8 * n);
        for (size_t s = 0; s < n; ++s)
            for (int c = 0; c < 8; ++c) sortedResults[8 * s + c] = float(sorted[s].k) + 0.125f * c;
        cl::Buffer results = device.allocate<float>(8 * n, CL_MEM_READ_WRITE, "test: results");
        scatterResults(device, o, device.upload(sortedResults), 8, results);
        const std::vector<float> back = device.download<float>(results, 8 * n);
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 8; ++c) ASSERT_EQ(back[8 * i + c], float(i) + 0.125f * c) << "query " << i;
    }
}

TEST(QueryOrder, NearbyQueriesShareKeysAndBadArgumentsAreRefused) {
    // Same cell, same key; a neighbouring cell along x differs in the lowest bit.
    EXPECT_EQ(queryOrderKey(0.01f, 0.02f, 0.03f, 0.1f), queryOrderKey(0.09f, 0.08f, 0.07f, 0.1f));
    EXPECT_EQ(queryOrderKey(0.15f, 0.0f, 0.0f, 0.1f) ^ queryOrderKey(0.05f, 0.0f, 0.0f, 0.1f), 1u);
    EXPECT_LT(queryOrderKey(1e30f, -1e30f, 3.0f, 0.1f), 1u << kQueryOrderKeyBits);
    Device& device = test::testDevice();
    const cl::Buffer none = device.allocate<PclEstimateQuery>(1, CL_MEM_READ_WRITE, "test: none");
    EXPECT_THROW(orderQueries(device, none, 1, 0.0f), InternalError);
    EXPECT_THROW(orderQueries(device, none, 1, INFINITY), InternalError);
    const QueryOrder empty = orderQueries(device, none, 0, 1.0f);
    cl::Buffer out = device.allocate<float>(4, CL_MEM_READ_WRITE, "test: out");
    EXPECT_THROW(scatterResults(device, empty, out, 6, out), InternalError);
}

}  // namespace
}  // namespace pcl
