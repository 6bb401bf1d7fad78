#include "pipeline/estimate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/clock.h"
#include "core/error.h"
#include "core/math.h"
#include "device/work_group.h"

namespace pcl {
namespace {

// cos θ, sin θ, cos φ, sin φ at the centres of the direction bytes' cells (kernels/README.md,
// "estimate"): θ = (b + 0.5)·π/256, φ = (b as a signed byte + 0.5)·π/128, in float.
std::vector<float> directionTable() {
    std::vector<float> t(1024);
    for (uint32_t b = 0; b < 256; ++b) {
        const float theta = (float(b) + 0.5f) * (kPi / 256.0f);
        const float phi = (float(b >= 128 ? int(b) - 256 : int(b)) + 0.5f) * (kPi / 128.0f);
        t[b] = std::cos(theta);
        t[256 + b] = std::sin(theta);
        t[512 + b] = std::cos(phi);
        t[768 + b] = std::sin(phi);
    }
    return t;
}

}  // namespace

// ---- PhotonMapOnDevice -------------------------------------------------------------------

PhotonMapOnDevice::PhotonMapOnDevice(Device& device, const std::vector<PclPhoton>& map, KnnStructure structure,
                                     float maxRadius)
    : structure_(structure), count_(map.size()), maxRadius_(maxRadius) {
    const auto t0 = std::chrono::steady_clock::now();
    float lo[3] = {0.0f, 0.0f, 0.0f};
    if (!map.empty()) {
        lo[0] = map[0].x, lo[1] = map[0].y, lo[2] = map[0].z;
        for (const PclPhoton& p : map) {
            lo[0] = std::min(lo[0], p.x);
            lo[1] = std::min(lo[1], p.y);
            lo[2] = std::min(lo[2], p.z);
        }
    }
    photons_ = device.upload(map, CL_MEM_READ_ONLY, "estimate: photon map");
    build(device, lo);
    device.finish();
    buildSeconds_ = since(t0);
}

PhotonMapOnDevice::PhotonMapOnDevice(Device& device, const cl::Buffer& photons, size_t count, KnnStructure structure,
                                     float maxRadius, const float lo[3])
    : structure_(structure), count_(count), maxRadius_(maxRadius), photons_(photons) {
    const auto t0 = std::chrono::steady_clock::now();
    build(device, lo);
    device.finish();
    buildSeconds_ = since(t0);
}

void PhotonMapOnDevice::build(Device& device, const float lo[3]) {
    if (structure_ == KnnStructure::KdTree) {
        tree_ = packKdTree(device, buildKdTree(device, photons_, count_));
        return;
    }
    if (!(maxRadius_ > 0.0f) || !std::isfinite(maxRadius_))
        throw InternalError("estimate: the hash grid needs a positive finite maxRadius, got " +
                            std::to_string(maxRadius_));
    if (count_ > (size_t(1) << 31))
        throw InputError("estimate: " + std::to_string(count_) + " photons exceed the hash grid's 32-bit table");
    PclGridParams g{};  // as hashGridParams, with the caller's bounds minimum
    g.ox = lo[0], g.oy = lo[1], g.oz = lo[2];
    g.cellSize = 2.0f * maxRadius_;
    g.invCellSize = 1.0f / g.cellSize;
    uint32_t table = 1;
    while (table < count_) table <<= 1;
    g.tableSize = table;
    g.photonCount = uint32_t(count_);
    grid_ = buildHashGrid(device, photons_, count_, g);
}

double PhotonMapOnDevice::search(Device& device, const cl::Buffer& queries, size_t queryCount, uint32_t maxK,
                                 DeviceKnnOutput& out, float firstRadius2) const {
    if (structure_ == KnnStructure::KdTree)
        return knnSearchKdTree(device, tree_, queries, queryCount, maxK, out, firstRadius2);
    return knnSearchHashGrid(device, grid_, queries, queryCount, maxK, out);
}

// ---- Estimates ---------------------------------------------------------------------------

size_t estimateBatchQueries(const Device& device, uint32_t maxK) {
    const size_t budget = device.info().maxAlloc / 4;
    const size_t perQuery = size_t(std::max(maxK, 1u)) * 8;
    return std::min<size_t>(std::max<size_t>(budget / perQuery, 1), size_t(1) << 20);
}

EstimateTiming estimateBuffers(Device& device, const PhotonMapOnDevice& map, const cl::Buffer& queries,
                               size_t queryCount, uint32_t maxK, const EstimateSettings& settings,
                               const DeviceScene* scene, cl::Buffer& results) {
    validateEstimateSettings(settings);
    knnHeapCapacity(maxK);  // InternalError outside 1..PCL_KNN_MAX_K
    if (settings.visibility && !scene)
        throw InternalError("estimate: the visibility test needs the scene on the device, got none");
    if (queryCount >= (size_t(1) << 32))
        throw InternalError("estimate: " + std::to_string(queryCount) + " queries exceed 32-bit indices");
    EstimateTiming timing;
    if (queryCount == 0) return timing;

    const std::string options = scene ? scene->geometry.programOptions() : std::string();
    auto convert =
        device.kernel<PclEstimateParams, cl_float, cl::Buffer, cl::Buffer>("estimate", "estimate_knn_queries", options);
    // The hash grid finds every photon only within its r_max: larger radii are clamped to it.
    const float searchRadius2 = map.structure() == KnnStructure::HashGrid ? map.maxRadius() * map.maxRadius()
                                                                          : std::numeric_limits<float>::infinity();
    auto estimate = device.kernel<PclEstimateParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                                  cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer>(
        "estimate", "estimate_irradiance", options);
    // Without a scene the BVH arguments are one-element placeholders the kernel never reads.
    cl::Buffer placeholder;
    if (!scene) placeholder = device.allocate<uint32_t>(1, CL_MEM_READ_ONLY, "estimate: BVH placeholder");
    const cl::Buffer& nodes = scene ? scene->geometry.nodes : placeholder;
    const cl::Buffer& packets = scene ? scene->geometry.packets : placeholder;
    const cl::Buffer& spheres = scene ? scene->geometry.spheres : placeholder;

    static const std::vector<float> table = directionTable();
    cl::Buffer dirTable = device.upload(table, CL_MEM_READ_ONLY, "estimate: direction table");
    const size_t batch = std::min(queryCount, estimateBatchQueries(device, maxK));
    timing.batchQueries = batch;
    cl::Buffer knnQueries = device.allocate<PclKnnQuery>(batch, CL_MEM_READ_WRITE, "estimate: kNN queries");
    for (size_t first = 0; first < queryCount; first += batch) {
        const size_t n = std::min(batch, queryCount - first);
        PclEstimateParams params = estimateParams(settings, uint32_t(first), uint32_t(n), maxK);
        params.maxSearchRadius2 = searchRadius2;
        cl::Event c = device.launchLocal("estimate", convert, wholeWorkGroups(n), workGroup(), params,
                                         cl_float(searchRadius2), queries, knnQueries);
        DeviceKnnOutput knn;
        timing.knnSeconds += map.search(device, knnQueries, n, maxK, knn, settings.firstRadius2);
        cl::Event e = device.launchLocal("estimate", estimate, wholeWorkGroups(n), workGroup(), params, queries,
                                         map.photons(), knn.counts, knn.indices, knn.dist2, knn.radius2, nodes, packets,
                                         spheres, dirTable, results);
        e.wait();
        timing.estimateSeconds += Device::elapsedSeconds(c) + Device::elapsedSeconds(e);
        ++timing.batches;
    }
    return timing;
}

}  // namespace pcl
