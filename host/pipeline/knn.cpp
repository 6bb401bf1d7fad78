#include "pipeline/knn.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>

#include "core/error.h"

namespace pcl {
namespace {

// Work-group size of the search launches: fixed, as PoCL compiles a kernel per work-group size.
constexpr size_t kKnnGroup = 64;
cl::NDRange knnGlobalRange(size_t n) { return cl::NDRange((n + kKnnGroup - 1) / kKnnGroup * kKnnGroup); }

std::string capOption(uint32_t maxK) { return "-DPCL_KNN_CAP=" + std::to_string(knnHeapCapacity(maxK)); }

DeviceKnnOutput allocateOutput(Device& device, size_t queryCount, uint32_t maxK) {
    DeviceKnnOutput out;
    out.stride = maxK;
    out.queries = queryCount;
    out.counts = device.allocate<uint32_t>(queryCount);
    out.indices = device.allocate<uint32_t>(queryCount * maxK);
    out.dist2 = device.allocate<float>(queryCount * maxK);
    out.radius2 = device.allocate<float>(queryCount);
    return out;
}

KnnResult download(Device& device, const DeviceKnnOutput& out) {
    KnnResult r;
    r.stride = out.stride;
    r.counts = device.download<uint32_t>(out.counts, out.queries);
    r.indices = device.download<uint32_t>(out.indices, out.queries * out.stride);
    r.dist2 = device.download<float>(out.dist2, out.queries * out.stride);
    r.radius2 = device.download<float>(out.radius2, out.queries);
    return r;
}

double seconds(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}


// TEMPORARY until pipeline/kdtree.h lands: Jensen's left-balanced tree built on the host from
// kernels/README.md ("kd-tree"), so knnOnDevice and checkKnn can search a kd-tree meanwhile.
uint32_t floatKey(float f) {
    uint32_t b;
    std::memcpy(&b, &f, 4);
    return (b & 0x80000000u) ? ~b : (b ^ 0x80000000u);
}

void balanceSubtree(const std::vector<PclPhoton>& map, std::vector<uint32_t>& ids, size_t lo, size_t hi, size_t node,
                    std::vector<PclPhoton>& nodes, std::vector<uint32_t>& nodeIndex) {
    const size_t n = hi - lo;
    if (n == 0) return;
    float mn[3] = {INFINITY, INFINITY, INFINITY}, mx[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = lo; i < hi; ++i) {
        const float c[3] = {map[ids[i]].x, map[ids[i]].y, map[ids[i]].z};
        for (int a = 0; a < 3; ++a) mn[a] = std::min(mn[a], c[a]), mx[a] = std::max(mx[a], c[a]);
    }
    int axis = 0;
    for (int a = 1; a < 3; ++a)
        if (mx[a] - mn[a] > mx[axis] - mn[axis]) axis = a;
    auto coord = [&](uint32_t id) { return axis == 0 ? map[id].x : axis == 1 ? map[id].y : map[id].z; };
    std::sort(ids.begin() + lo, ids.begin() + hi, [&](uint32_t a, uint32_t b) {
        const uint32_t ka = floatKey(coord(a)), kb = floatKey(coord(b));
        return ka != kb ? ka < kb : a < b;
    });
    size_t left = 0;
    if (n > 1) {
        int h = 0;
        while ((size_t(2) << h) <= n) ++h;  // h = floor(log2 n)
        const size_t half = size_t(1) << (h - 1);
        left = half - 1 + std::min(half, n - ((size_t(1) << h) - 1));
    }
    const uint32_t id = ids[lo + left];
    nodes[node] = map[id];
    nodes[node].packed = (nodes[node].packed & ~PCL_PHOTON_AXIS_MASK) | (uint32_t(axis) << PCL_PHOTON_AXIS_SHIFT);
    nodeIndex[node] = id;
    balanceSubtree(map, ids, lo, lo + left, 2 * node + 1, nodes, nodeIndex);
    balanceSubtree(map, ids, lo + left + 1, hi, 2 * node + 2, nodes, nodeIndex);
}

}  // namespace

const char* knnStructureName(KnnStructure s) { return s == KnnStructure::KdTree ? "kd-tree" : "hash grid"; }

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

double knnSearchKdTree(Device& device, const DeviceKdTree& tree, const cl::Buffer& queries, size_t queryCount,
                       uint32_t maxK, DeviceKnnOutput& out) {
    out = allocateOutput(device, queryCount, maxK);
    if (queryCount == 0) return 0.0;
    auto k = device.kernel<cl::Buffer, cl::Buffer, cl_uint, cl::Buffer, cl_uint, cl_uint, cl::Buffer, cl::Buffer,
                           cl::Buffer, cl::Buffer>("knn", "knn_kdtree", capOption(maxK));
    cl::Event e = device.launchLocal("knn", k, knnGlobalRange(queryCount), cl::NDRange(kKnnGroup), tree.nodes,
                                     tree.nodeIndex, cl_uint(tree.count), queries, cl_uint(queryCount), cl_uint(maxK),
                                     out.counts, out.indices, out.dist2, out.radius2);
    e.wait();
    return Device::elapsedSeconds(e);
}

double knnSearchHashGrid(Device& device, const DeviceHashGrid& grid, const cl::Buffer& queries, size_t queryCount,
                         uint32_t maxK, DeviceKnnOutput& out) {
    out = allocateOutput(device, queryCount, maxK);
    if (queryCount == 0) return 0.0;
    auto k = device.kernel<PclGridParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl_uint, cl_uint, cl::Buffer,
                           cl::Buffer, cl::Buffer, cl::Buffer>("knn", "knn_hashgrid", capOption(maxK));
    cl::Event e = device.launchLocal("knn", k, knnGlobalRange(queryCount), cl::NDRange(kKnnGroup), grid.params,
                                     grid.points, grid.cellStart, grid.cellEnd, queries, cl_uint(queryCount),
                                     cl_uint(maxK), out.counts, out.indices, out.dist2, out.radius2);
    e.wait();
    return Device::elapsedSeconds(e);
}

KnnResult knnKdTreeOnDevice(Device& device, const std::vector<PclPhoton>& heapNodes,
                            const std::vector<uint32_t>& nodeIndex, const std::vector<PclKnnQuery>& queries) {
    if (heapNodes.size() != nodeIndex.size())
        throw InputError("knn: " + std::to_string(heapNodes.size()) + " kd-tree nodes with " +
                         std::to_string(nodeIndex.size()) + " photon indices");
    const uint32_t maxK = knnMaxK(queries);
    const auto t0 = std::chrono::steady_clock::now();
    DeviceKdTree tree{device.upload(heapNodes), device.upload(nodeIndex), heapNodes.size()};
    device.finish();
    const double build = seconds(t0);
    cl::Buffer q = device.upload(queries);
    DeviceKnnOutput out;
    const double search = knnSearchKdTree(device, tree, q, queries.size(), maxK, out);
    KnnResult r = download(device, out);
    r.searchSeconds = search;
    r.buildSeconds = build;
    return r;
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
    cl::Buffer photons = device.upload(map);
    DeviceHashGrid grid = buildHashGrid(device, photons, map.size(), params);
    device.finish();
    const double build = seconds(t0);
    cl::Buffer q = device.upload(queries);
    DeviceKnnOutput out;
    const double search = knnSearchHashGrid(device, grid, q, queries.size(), maxK, out);
    KnnResult r = download(device, out);
    r.searchSeconds = search;
    r.buildSeconds = build;
    return r;
}

KnnResult knnOnDevice(Device& device, const std::vector<PclPhoton>& map, KnnStructure structure,
                      const std::vector<PclKnnQuery>& queries) {
    if (structure == KnnStructure::HashGrid) return knnHashGridOnDevice(device, map, queries);
    // TEMPORARY until pipeline/kdtree.h lands: the tree built on the host.
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<uint32_t> ids(map.size());
    for (size_t i = 0; i < ids.size(); ++i) ids[i] = uint32_t(i);
    std::vector<PclPhoton> nodes(map.size());
    std::vector<uint32_t> nodeIndex(map.size());
    balanceSubtree(map, ids, 0, map.size(), 0, nodes, nodeIndex);
    const double build = seconds(t0);
    KnnResult r = knnKdTreeOnDevice(device, nodes, nodeIndex, queries);
    r.buildSeconds += build;
    return r;
}

}  // namespace pcl
