#include "pipeline/knn.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "core/clock.h"
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


// The common tail of the *OnDevice calls, once the structure is built: in batches of
// knnQueryBatch queries (so no output buffer passes the device's max allocation, capped or
// not), uploads the batch, runs `search(queryBuffer, count, out)` (one search launch, returning
// its device seconds) and downloads it into its place. Queries are independent, so the result is
// the same bits whatever the batch.
template <class Search>
KnnResult searchAndDownload(Device& device, const std::vector<PclKnnQuery>& queries, uint32_t maxK,
                            double buildSeconds, Search search) {
    const size_t n = queries.size();
    const size_t batch = std::min(std::max<size_t>(n, 1),
                                  knnQueryBatch(device.info().maxAlloc, device.info().globalMem, maxK));
    KnnResult r;
    r.stride = maxK;
    r.counts.resize(n);
    r.indices.resize(n * maxK);
    r.dist2.resize(n * maxK);
    r.radius2.resize(n);
    r.buildSeconds = buildSeconds;
    if (n == 0) return r;
    cl::Buffer q = device.allocate<PclKnnQuery>(batch, CL_MEM_READ_ONLY, "knn: queries");
    for (size_t first = 0; first < n; first += batch) {
        const size_t m = std::min(batch, n - first);
        Device::guard("upload", [&] {
            device.queue().enqueueWriteBuffer(q, CL_TRUE, 0, m * sizeof(PclKnnQuery), queries.data() + first);
        });
        DeviceKnnOutput out;
        r.searchSeconds += search(q, m, out);
        Device::guard("download", [&] {
            cl::CommandQueue& cq = device.queue();
            cq.enqueueReadBuffer(out.counts, CL_FALSE, 0, m * 4, r.counts.data() + first);
            cq.enqueueReadBuffer(out.indices, CL_FALSE, 0, m * maxK * 4, r.indices.data() + first * maxK);
            cq.enqueueReadBuffer(out.dist2, CL_FALSE, 0, m * maxK * 4, r.dist2.data() + first * maxK);
            cq.enqueueReadBuffer(out.radius2, CL_TRUE, 0, m * 4, r.radius2.data() + first);
        });
    }
    return r;
}

}  // namespace

size_t knnQueryBatch(size_t maxAlloc, size_t globalMem, uint32_t maxK) {
    const size_t k = std::max<uint32_t>(maxK, 1);
    const size_t widest = std::max<size_t>(k * sizeof(uint32_t), sizeof(PclKnnQuery));  // bytes per query, largest buffer
    const size_t perQuery = sizeof(PclKnnQuery) + 2 * sizeof(uint32_t) + 2 * k * sizeof(uint32_t);
    size_t batch = std::min(maxAlloc / widest, globalMem / 4 / perQuery);
    batch = batch >= kWorkGroupSize ? batch / kWorkGroupSize * kWorkGroupSize : std::max<size_t>(batch, 1);
    return batch;
}

uint32_t knnHeapCapacity(uint32_t maxK) {
    if (maxK == 0 || maxK > PCL_KNN_MAX_K)
        throw InputError("knn: k = " + std::to_string(maxK) + ", expected 1.." + std::to_string(PCL_KNN_MAX_K));
    for (uint32_t cap : {8u, 32u, 64u, 128u, 256u})
        if (maxK <= cap) return cap;
    return PCL_KNN_MAX_K;
}

uint32_t knnMaxK(const std::vector<PclKnnQuery>& queries) {
    uint32_t maxK = 1;
    for (size_t i = 0; i < queries.size(); ++i) {
        const PclKnnQuery& q = queries[i];
        if (q.k == 0 || q.k > PCL_KNN_MAX_K)
            throw InputError("knn: query " + std::to_string(i) + " asks k = " + std::to_string(q.k) + ", expected 1.." +
                             std::to_string(PCL_KNN_MAX_K));
        if (!(q.maxRadius2 >= 0.0f))
            throw InputError("knn: query " + std::to_string(i) + " has maxRadius2 = " + std::to_string(q.maxRadius2) +
                             ", expected ≥ 0");
        maxK = std::max(maxK, q.k);
    }
    return maxK;
}

KnnKdTree packKdTree(Device& device, const DeviceKdTree& tree) {
    if (tree.count >= (size_t(1) << 30))
        throw InputError("knn: a kd-tree of " + std::to_string(tree.count) + " photons exceeds the 2^30 of the packed index");
    KnnKdTree packed;
    packed.count = tree.count;
    packed.nodes = device.allocate<cl_float4>(tree.count, CL_MEM_READ_WRITE, "knn: packed kd-tree");
    // Any specialisation holds the packing kernel: the smallest one.
    auto k = device.kernel<cl::Buffer, cl::Buffer, cl_uint, cl::Buffer>("knn", "knn_pack_kdtree", capOption(1));
    device.launchLocal("knn", k, wholeWorkGroups(tree.count), workGroup(), tree.photons, tree.index,
                       cl_uint(tree.count), packed.nodes);
    return packed;
}

double knnSearchKdTree(Device& device, const KnnKdTree& tree, const cl::Buffer& queries, size_t queryCount,
                       uint32_t maxK, DeviceKnnOutput& out) {
    out = allocateOutput(device, queryCount, maxK);
    if (queryCount == 0) return 0.0;
    auto k = device.kernel<cl::Buffer, cl_uint, cl::Buffer, cl_uint, cl_uint, cl::Buffer, cl::Buffer, cl::Buffer,
                           cl::Buffer>("knn", "knn_kdtree", capOption(maxK));
    cl::Event e = device.launchLocal("knn", k, wholeWorkGroups(queryCount), workGroup(), tree.nodes,
                                     cl_uint(tree.count), queries, cl_uint(queryCount), cl_uint(maxK), out.counts,
                                     out.indices, out.dist2, out.radius2);
    e.wait();
    return Device::elapsedSeconds(e);
}

double knnSearchHashGrid(Device& device, const DeviceHashGrid& grid, const cl::Buffer& queries, size_t queryCount,
                         uint32_t maxK, DeviceKnnOutput& out) {
    out = allocateOutput(device, queryCount, maxK);
    if (queryCount == 0) return 0.0;
    auto k = device.kernel<PclGridParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl_uint, cl_uint, cl::Buffer,
                           cl::Buffer, cl::Buffer, cl::Buffer>("knn", "knn_hashgrid", capOption(maxK));
    cl::Event e = device.launchLocal("knn", k, wholeWorkGroups(queryCount), workGroup(), grid.params,
                                     grid.points, grid.cellStart, grid.cellEnd, queries, cl_uint(queryCount),
                                     cl_uint(maxK), out.counts, out.indices, out.dist2, out.radius2);
    e.wait();
    return Device::elapsedSeconds(e);
}

KnnResult knnSearchOnDevice(Device& device, const KnnKdTree& tree, const std::vector<PclKnnQuery>& queries) {
    const uint32_t maxK = knnMaxK(queries);
    return searchAndDownload(device, queries, maxK, 0.0, [&](const cl::Buffer& q, size_t count, DeviceKnnOutput& out) {
        return knnSearchKdTree(device, tree, q, count, maxK, out);
    });
}

KnnResult knnSearchOnDevice(Device& device, const DeviceHashGrid& grid, const std::vector<PclKnnQuery>& queries) {
    const uint32_t maxK = knnMaxK(queries);
    return searchAndDownload(device, queries, maxK, 0.0, [&](const cl::Buffer& q, size_t count, DeviceKnnOutput& out) {
        return knnSearchHashGrid(device, grid, q, count, maxK, out);
    });
}

KnnResult knnKdTreeOnDevice(Device& device, const std::vector<PclPhoton>& heapNodes,
                            const std::vector<uint32_t>& nodeIndex, const std::vector<PclKnnQuery>& queries) {
    if (heapNodes.size() != nodeIndex.size())
        throw InputError("knn: " + std::to_string(heapNodes.size()) + " kd-tree nodes with " +
                         std::to_string(nodeIndex.size()) + " photon indices");
    const uint32_t maxK = knnMaxK(queries);
    const auto t0 = std::chrono::steady_clock::now();
    DeviceKdTree built;
    built.photons = device.upload(heapNodes, CL_MEM_READ_ONLY, "kd-tree: nodes");
    built.index = device.upload(nodeIndex, CL_MEM_READ_ONLY, "kd-tree: node index");
    built.count = heapNodes.size();
    const KnnKdTree tree = packKdTree(device, built);
    device.finish();
    return searchAndDownload(device, queries, maxK, since(t0),
                             [&](const cl::Buffer& q, size_t count, DeviceKnnOutput& out) {
                                 return knnSearchKdTree(device, tree, q, count, maxK, out);
                             });
}

KnnResult knnHashGridOnDevice(Device& device, const std::vector<PclPhoton>& map, const std::vector<PclKnnQuery>& queries) {
    const uint32_t maxK = knnMaxK(queries);
    float maxRadius2 = 0.0f;
    for (const PclKnnQuery& q : queries) maxRadius2 = std::max(maxRadius2, q.maxRadius2);
    if (!std::isfinite(maxRadius2))
        throw InputError("knn: the hash grid needs a finite search radius (a query has maxRadius2 = inf)");
    float rMax = std::sqrt(maxRadius2);
    if (!(rMax > 0.0f)) rMax = 1.0f;  // every radius 0: any cell size finds the photons at the query
    const auto t0 = std::chrono::steady_clock::now();
    const PclGridParams params = hashGridParams(map, rMax);
    cl::Buffer photons = device.upload(map, CL_MEM_READ_ONLY, "hash grid: photons");
    DeviceHashGrid grid = buildHashGrid(device, photons, map.size(), params);
    device.finish();
    return searchAndDownload(device, queries, maxK, since(t0),
                             [&](const cl::Buffer& q, size_t count, DeviceKnnOutput& out) {
                                 return knnSearchHashGrid(device, grid, q, count, maxK, out);
                             });
}

KnnResult knnOnDevice(Device& device, const std::vector<PclPhoton>& map, KnnStructure structure,
                      const std::vector<PclKnnQuery>& queries) {
    if (structure == KnnStructure::HashGrid) return knnHashGridOnDevice(device, map, queries);
    const uint32_t maxK = knnMaxK(queries);
    const auto t0 = std::chrono::steady_clock::now();
    cl::Buffer photons = device.upload(map, CL_MEM_READ_ONLY, "kd-tree: photons");
    const KnnKdTree tree = packKdTree(device, buildKdTree(device, photons, map.size()));
    device.finish();
    return searchAndDownload(device, queries, maxK, since(t0),
                             [&](const cl::Buffer& q, size_t count, DeviceKnnOutput& out) {
                                 return knnSearchKdTree(device, tree, q, count, maxK, out);
                             });
}

}  // namespace pcl
