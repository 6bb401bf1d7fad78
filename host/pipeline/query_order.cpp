#include "pipeline/query_order.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "device/work_group.h"
#include "pipeline/sort.h"
#include "shared/morton.h"
#include "shared/types.h"

namespace pcl {
namespace {

const char* const kStage = "query_order";

uint32_t cellOf(float x, float invCell) {
    const float c = std::floor(x * invCell);
    return uint32_t(int32_t(c == c ? std::clamp(c, -1.0e9f, 1.0e9f) : 0.0f));
}

}  // namespace

uint32_t queryOrderKey(float x, float y, float z, float cell) {
    const float inv = 1.0f / cell;
    return morton_key8(cellOf(x, inv), cellOf(y, inv), cellOf(z, inv));
}

QueryOrder orderQueries(Device& device, const cl::Buffer& queries, size_t count, float cell) {
    if (!(cell > 0.0f) || !std::isfinite(cell))
        throw InternalError("query order: cell " + std::to_string(cell) + ": expected a positive finite size");
    if (count >= (size_t(1) << 31))
        throw InternalError("query order: " + std::to_string(count) + " queries (at most 2^31 - 1)");
    QueryOrder o;
    o.count = count;
    cl::Buffer keys = device.allocate<uint32_t>(count, CL_MEM_READ_WRITE, "query order: keys");
    o.order = device.allocate<uint32_t>(count, CL_MEM_READ_WRITE, "query order: order");
    o.sorted = device.allocate<PclEstimateQuery>(count, CL_MEM_READ_WRITE, "query order: sorted queries");
    if (count == 0) return o;
    auto keysK = device.kernel<cl::Buffer, cl_uint, cl_float, cl::Buffer, cl::Buffer>(kStage, "query_order_keys");
    auto gather = device.kernel<cl::Buffer, cl::Buffer, cl_uint, cl::Buffer>(kStage, "query_order_gather");
    device.launchLocal(kStage, keysK, wholeWorkGroups(count), workGroup(), queries, cl_uint(count),
                       cl_float(1.0f / cell), keys, o.order);
    sortPairsOnDevice(device, keys, o.order, count, 32, kQueryOrderKeyBits);
    device.launchLocal(kStage, gather, wholeWorkGroups(count), workGroup(), queries, o.order, cl_uint(count), o.sorted);
    return o;
}

void scatterResults(Device& device, const QueryOrder& order, const cl::Buffer& sortedResults, uint32_t floats,
                    cl::Buffer& results) {
    if (floats == 0 || floats % 4 != 0)
        throw InternalError("query order: records of " + std::to_string(floats) + " floats: expected a multiple of 4");
    if (order.count == 0) return;
    auto scatter = device.kernel<cl::Buffer, cl::Buffer, cl_uint, cl_uint, cl::Buffer>(kStage, "query_order_scatter");
    device.launchLocal(kStage, scatter, wholeWorkGroups(order.count), workGroup(), sortedResults, order.order,
                       cl_uint(order.count), cl_uint(floats / 4), results);
}

}  // namespace pcl
