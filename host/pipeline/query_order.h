// A space-filling-curve order of estimate queries on the device (kernels/query_order.cl): the
// queries sorted by the Morton code of their cell, so the searches of neighbouring work-items
// read the same tree nodes and photons. Searches answer each query alone, so running them in
// this order and putting the results back gives the same results, sooner.
//
//   QueryOrder o = orderQueries(device, queries, n, cell);  // o.sorted[s] = queries[o.order[s]]
//   ... search o.sorted into sortedResults ...
//   scatterResults(device, o, sortedResults, 4, results);   // 4-float results back in query order
#pragma once
#include <cstddef>
#include <cstdint>

#include "device/device.h"

namespace pcl {

// Bits of the sort key: 8 per axis (cells wrap modulo 256 per axis: only coherence suffers).
inline constexpr int kQueryOrderKeyBits = 24;

struct QueryOrder {
    cl::Buffer order;   // uint32[count]: the query at sorted position s
    cl::Buffer sorted;  // PclEstimateQuery[count] in that order
    size_t count = 0;
};

// The order for `count` PclEstimateQuery in `queries`, cells of side `cell` (> 0, finite).
// Ties keep the query order (the sort is stable), so the order depends on the queries alone.
QueryOrder orderQueries(Device& device, const cl::Buffer& queries, size_t count, float cell);

// results[order[s]] = sortedResults[s] for records of `floats` floats (a multiple of 4).
void scatterResults(Device& device, const QueryOrder& order, const cl::Buffer& sortedResults, uint32_t floats,
                    cl::Buffer& results);

// The Morton key query_order_keys gives a point (the twin of the kernel, for the tests).
uint32_t queryOrderKey(float x, float y, float z, float cell);

}  // namespace pcl
