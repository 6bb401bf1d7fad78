#include "pipeline/knn.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "device/work_group.h"

namespace pcl {
namespace {

// Work-group size of the search launches: fixed, as PoCL compiles a kernel per work-group size.

std::string capOption(uint32_t maxK) { return "-DPCL_KNN_CAP=" + std::to_string(knnHeapCapacity(maxK)); }

DeviceKnnOutput allocateOutput(Device& device, size_t queryCount, uint32_t maxK) {
    DeviceKnnOutput out;
    out.stride = maxK;
    out.queries = queryCount;
    const cl_mem_flags wo = CL_MEM_WRITE_ONLY;
    out.counts = device.allocate<uint32_t>(queryCount, wo, "knn: counts");
    out.indices = device.allocate<uint32_t>(queryCount * maxK, wo, "knn: indices");
    out.dist2 = device.allocate<float>(queryCount * maxK, wo, "knn: dist2");
    out.radius2 = device.allocate<float>(queryCount, wo, "knn: radius2");
    return out;
}

}  // namespace

size_t knnQueryBatch(size_t maxAlloc, size_t globalMem, uint32_t maxK) {
    const size_t k = std::max<uint32_t>(maxK, 1);
    const size_t widest =
        std::max<size_t>(k * sizeof(uint32_t), sizeof(PclKnnQuery));  // bytes per query, largest buffer
    const size_t perQuery = sizeof(PclKnnQuery) + 2 * sizeof(uint32_t) + 2 * k * sizeof(uint32_t);
    size_t batch = std::min(maxAlloc / widest, globalMem / 4 / perQuery);
    batch = batch >= kWorkGroupSize ? batch / kWorkGroupSize * kWorkGroupSize : std::max<size_t>(batch, 1);
    return batch;
}

uint32_t knnHeapCapacity(uint32_t maxK) {
    if (maxK == 0 || maxK > PCL_KNN_MAX_K)
        throw InternalError("knn: k = " + std::to_string(maxK) + ", expected 1.." + std::to_string(PCL_KNN_MAX_K));
    for (uint32_t cap : {8u, 32u, 64u, 128u, 256u})
        if (maxK <= cap) return cap;
    return PCL_KNN_MAX_K;
}

uint32_t knnMaxK(const std::vector<PclKnnQuery>& queries) {
    uint32_t maxK = 1;
    for (size_t i = 0; i < queries.size(); ++i) {
        const PclKnnQuery& q = queries[i];
        if (q.k == 0 || q.k > PCL_KNN_MAX_K)
            throw InternalError("knn: query " + std::to_string(i) + " asks k = " + std::to_string(q.k) +
                                ", expected 1.." + std::to_string(PCL_KNN_MAX_K));
        if (!(q.maxRadius2 >= 0.0f))
            throw InternalError("knn: query " + std::to_string(i) +
                                " has maxRadius2 = " + std::to_string(q.maxRadius2) + ", expected ≥ 0");
        maxK = std::max(maxK, q.k);
    }
    return maxK;
}

uint32_t knnBucketFirst(size_t count) {
    int levels = 0;
    for (size_t v = count; v; v >>= 1) ++levels;
    return levels <= 3 ? 0u : (uint32_t(1) << (levels - 3)) - 1u;
}

size_t knnPackedKdTreeElements(size_t count) { return count + PCL_KD_BUCKET_PAD_FLOATS / 4; }

KnnKdTree packKdTree(Device& device, const DeviceKdTree& tree) {
    if (tree.count >= (size_t(1) << 30))
        throw InputError("knn: a kd-tree of " + std::to_string(tree.count) +
                         " photons exceeds the 2^30 of the packed index");
    KnnKdTree packed;
    packed.count = tree.count;
    packed.bucketFirst = knnBucketFirst(tree.count);
    packed.nodes =
        device.allocate<cl_float4>(knnPackedKdTreeElements(tree.count), CL_MEM_READ_WRITE, "knn: packed kd-tree");
    // Any specialisation holds the packing kernel: the smallest one.
    auto k =
        device.kernel<cl::Buffer, cl::Buffer, cl_uint, cl_uint, cl::Buffer>("knn", "knn_pack_kdtree", capOption(1));
    device.launchLocal("knn", k, wholeWorkGroups(tree.count), workGroup(), tree.photons, tree.index,
                       cl_uint(tree.count), cl_uint(packed.bucketFirst), packed.nodes);
    return packed;
}

double knnSearchKdTree(Device& device, const KnnKdTree& tree, const cl::Buffer& queries, size_t queryCount,
                       uint32_t maxK, DeviceKnnOutput& out, float firstRadius2) {
    if (std::isnan(firstRadius2) || firstRadius2 < 0.0f)
        throw InternalError("knn: first search radius² " + std::to_string(firstRadius2) + ": expected ≥ 0 or ∞");
    out = allocateOutput(device, queryCount, maxK);
    if (queryCount == 0) return 0.0;
    auto k = device.kernel<cl::Buffer, cl_uint, cl_uint, cl_float, cl::Buffer, cl_uint, cl_uint, cl::Buffer, cl::Buffer,
                           cl::Buffer, cl::Buffer>("knn", "knn_kdtree", capOption(maxK));
    cl::Event e = device.launchLocal("knn", k, wholeWorkGroups(queryCount), workGroup(), tree.nodes,
                                     cl_uint(tree.count), cl_uint(tree.bucketFirst), cl_float(firstRadius2), queries,
                                     cl_uint(queryCount), cl_uint(maxK), out.counts, out.indices, out.dist2,
                                     out.radius2);
    e.wait();
    return Device::elapsedSeconds(e);
}

double knnSearchHashGrid(Device& device, const DeviceHashGrid& grid, const cl::Buffer& queries, size_t queryCount,
                         uint32_t maxK, DeviceKnnOutput& out) {
    out = allocateOutput(device, queryCount, maxK);
    if (queryCount == 0) return 0.0;
    auto k = device.kernel<PclGridParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl_uint, cl_uint, cl::Buffer,
                           cl::Buffer, cl::Buffer, cl::Buffer>("knn", "knn_hashgrid", capOption(maxK));
    cl::Event e = device.launchLocal("knn", k, wholeWorkGroups(queryCount), workGroup(), grid.params, grid.points,
                                     grid.cellStart, grid.cellEnd, queries, cl_uint(queryCount), cl_uint(maxK),
                                     out.counts, out.indices, out.dist2, out.radius2);
    e.wait();
    return Device::elapsedSeconds(e);
}

}  // namespace pcl
