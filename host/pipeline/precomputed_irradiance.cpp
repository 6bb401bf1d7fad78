#include "pipeline/precomputed_irradiance.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "core/clock.h"
#include "core/error.h"
#include "device/work_group.h"
#include "pipeline/kdtree.h"
#include "pipeline/knn.h"
#include "pipeline/query_order.h"

namespace pcl {
namespace {

const char* const kStage = "precomputed_irradiance";

// Floats of the lookup's buckets: the rows of every node on the bucket levels, and the padding.
size_t irradianceBucketFloats(size_t count) {
    return PCL_IRRADIANCE_BUCKET_ROWS * (count - knnBucketFirst(count)) + PCL_KD_BUCKET_PAD_FLOATS;
}

}  // namespace

std::vector<IrradianceBufferSize> precomputedIrradianceBuffers(size_t records, uint32_t every, size_t lookupQueries) {
    const size_t count = records == 0 || every == 0 ? 0 : (records - 1) / every + 1;
    std::vector<IrradianceBufferSize> b = {
        {"precomputed irradiance: points", count, sizeof(PclIrradiancePoint)},
        {"precomputed irradiance: estimate queries", count, sizeof(PclEstimateQuery)},
        {"precomputed irradiance: covers", count, sizeof(float)},
        {"precomputed irradiance: nondirect irradiance", count, sizeof(cl_float4)},
        {"precomputed irradiance: other photons", records - count, sizeof(PclPhoton)},
        {"precomputed irradiance: estimates", count, sizeof(PclEstimate)},
        {"query order: keys", count, sizeof(uint32_t)},
        {"query order: order", count, sizeof(uint32_t)},
        {"query order: sorted queries", count, sizeof(PclEstimateQuery)},
        {"precomputed irradiance: tree nodes", count, sizeof(PclIrradiancePoint)},
        {"precomputed irradiance: tree covers", count, sizeof(float)},
        {"precomputed irradiance: tree nondirect irradiance", count, sizeof(cl_float4)},
        {"precomputed irradiance: tree buckets", irradianceBucketFloats(count), sizeof(float)},
        {"precomputed irradiance: tree input", count, sizeof(PclPhoton)},
    };
    if (lookupQueries) {
        b.push_back({"precomputed irradiance: lookups", lookupQueries, sizeof(cl_float4)});
        b.push_back({"precomputed irradiance: chosen points", lookupQueries, sizeof(uint32_t)});
    }
    return b;
}

DeviceIrradianceMap precomputeIrradiance(Device& device, const cl::Buffer& photons, size_t n,
                                         const PrecomputedIrradianceOptions& options, const DeviceScene* scene,
                                         const float* lo) {
    validatePrecomputedIrradianceOptions(options);
    if (n >= (size_t(1) << 30))
        throw InputError("precomputed irradiance: a global map of " + std::to_string(n) +
                         " photons exceeds the 2^30 of the stored photon index");
    if (options.estimate.structure == KnnStructure::HashGrid && !lo)
        throw InternalError(
            "precomputed irradiance: a hash grid over the other photons needs the map's bounds minimum");
    const size_t count = n == 0 ? 0 : (n - 1) / options.every + 1;
    const size_t others = n - count;
    cl::Buffer points = device.allocate<PclIrradiancePoint>(count, CL_MEM_READ_WRITE, "precomputed irradiance: points");
    cl::Buffer queries =
        device.allocate<PclEstimateQuery>(count, CL_MEM_READ_WRITE, "precomputed irradiance: estimate queries");
    cl::Buffer cover = device.allocate<float>(count, CL_MEM_READ_WRITE, "precomputed irradiance: covers");
    cl::Buffer nondirect =
        device.allocate<cl_float4>(count, CL_MEM_READ_WRITE, "precomputed irradiance: nondirect irradiance");
    cl::Buffer otherPhotons =
        device.allocate<PclPhoton>(others, CL_MEM_READ_WRITE, "precomputed irradiance: other photons");
    auto select = device.kernel<cl::Buffer, cl_uint, cl_uint, cl_float, cl_uint, cl::Buffer, cl::Buffer>(
        kStage, "precomputed_irradiance_select");
    auto unselected =
        device.kernel<cl::Buffer, cl_uint, cl_uint, cl::Buffer>(kStage, "precomputed_irradiance_unselected");
    const cl::Event selected = device.launchLocal(
        kStage, select, wholeWorkGroups(count), workGroup(), photons, cl_uint(n), cl_uint(options.every),
        cl_float(options.maxRadius * options.maxRadius), cl_uint(options.k), points, queries);
    const cl::Event split = device.launchLocal(kStage, unselected, wholeWorkGroups(n), workGroup(), photons, cl_uint(n),
                                               cl_uint(options.every), otherPhotons);
    device.finish();
    IrradianceTiming timing;
    if (count) timing.selectSeconds = Device::elapsedSeconds(selected) + Device::elapsedSeconds(split);

    if (count) {
        const float zero[3] = {0.0f, 0.0f, 0.0f};
        const PhotonMapOnDevice otherMap(device, otherPhotons, others, options.estimate.structure, options.maxRadius,
                                         lo ? lo : zero);
        timing.mapSeconds = otherMap.buildSeconds();
        // The estimates in Morton order of cells of r_max / 8 (the selection is in deposit order,
        // all over the scene): neighbouring work-items then read the same tree nodes and photons
        // (cornell-box: the kNN 1.3-3x faster, more so on a loaded machine). Results unchanged.
        const QueryOrder order = orderQueries(device, queries, count, options.maxRadius / 8.0f);
        cl::Buffer estimates =
            device.allocate<PclEstimate>(count, CL_MEM_READ_WRITE, "precomputed irradiance: estimates");
        timing.estimate =
            estimateBuffers(device, otherMap, order.sorted, count, options.k, options.estimate, scene, estimates);
        const float scale = float(options.every) / float(options.every - 1);
        const float coverScale2 = options.coverFactor * options.coverFactor;
        auto store =
            device.kernel<cl::Buffer, cl::Buffer, cl_float, cl_float, cl_uint, cl::Buffer, cl::Buffer, cl::Buffer>(
                kStage, "precomputed_irradiance_store");
        device.launchLocal(kStage, store, wholeWorkGroups(count), workGroup(), estimates, order.order, cl_float(scale),
                           cl_float(coverScale2), cl_uint(count), points, cover, nondirect);
    }
    DeviceIrradianceMap map =
        buildIrradianceTree(device, points, cover, nondirect, count, options.estimate.minNormalCos);
    timing.treeSeconds = map.timing.treeSeconds;
    map.timing = timing;
    return map;
}

DeviceIrradianceMap precomputeIrradiance(Device& device, const std::vector<PclPhoton>& map,
                                         const PrecomputedIrradianceOptions& options, const DeviceScene* scene) {
    float lo[3] = {0.0f, 0.0f, 0.0f};
    if (!map.empty()) {
        lo[0] = map[0].x, lo[1] = map[0].y, lo[2] = map[0].z;
        for (const PclPhoton& p : map)
            lo[0] = std::min(lo[0], p.x), lo[1] = std::min(lo[1], p.y), lo[2] = std::min(lo[2], p.z);
    }
    return precomputeIrradiance(device, device.upload(map), map.size(), options, scene, lo);
}

DeviceIrradianceMap buildIrradianceTree(Device& device, const cl::Buffer& points, const cl::Buffer& cover,
                                        const cl::Buffer& nondirect, size_t count, float minNormalCos) {
    if (count >= (size_t(1) << 30))
        throw InputError("precomputed irradiance: " + std::to_string(count) +
                         " points exceed the 2^30 of the stored photon index");
    if (std::isnan(minNormalCos)) throw InternalError("precomputed irradiance: minNormalCos is NaN");
    const auto t0 = std::chrono::steady_clock::now();
    DeviceIrradianceMap map;
    map.points = points;
    map.cover = cover;
    map.nondirect = nondirect;
    map.count = count;
    map.minNormalCos = minNormalCos;
    map.nodes = device.allocate<PclIrradiancePoint>(count, CL_MEM_READ_WRITE, "precomputed irradiance: tree nodes");
    map.nodeCover = device.allocate<float>(count, CL_MEM_READ_WRITE, "precomputed irradiance: tree covers");
    map.nodeNondirect =
        device.allocate<cl_float4>(count, CL_MEM_READ_WRITE, "precomputed irradiance: tree nondirect irradiance");
    if (count) {
        // The photon kd-tree builder orders the points (it reads only position; the normal word
        // rides along), then the pack copies each point into its heap slot with the split axis.
        cl::Buffer asPhotons =
            device.allocate<PclPhoton>(count, CL_MEM_READ_WRITE, "precomputed irradiance: tree input");
        auto toPhotons = device.kernel<cl::Buffer, cl_uint, cl::Buffer>(kStage, "precomputed_irradiance_as_photons");
        device.launchLocal(kStage, toPhotons, wholeWorkGroups(count), workGroup(), points, cl_uint(count), asPhotons);
        const DeviceKdTree tree = buildKdTree(device, asPhotons, count);
        auto pack = device.kernel<cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl_uint, cl::Buffer,
                                  cl::Buffer, cl::Buffer>(kStage, "precomputed_irradiance_pack");
        device.launchLocal(kStage, pack, wholeWorkGroups(count), workGroup(), tree.photons, tree.index, points, cover,
                           nondirect, cl_uint(count), map.nodes, map.nodeCover, map.nodeNondirect);
    }
    map.bucketFirst = knnBucketFirst(count);
    map.buckets = device.allocate<float>(irradianceBucketFloats(count), CL_MEM_READ_WRITE,
                                         "precomputed irradiance: tree buckets");
    if (count) {
        auto buckets = device.kernel<cl::Buffer, cl::Buffer, cl_uint, cl_uint, cl::Buffer>(
            kStage, "precomputed_irradiance_buckets");
        device.launchLocal(kStage, buckets, wholeWorkGroups(count - map.bucketFirst), workGroup(), map.nodes,
                           map.nodeCover, cl_uint(count), cl_uint(map.bucketFirst), map.buckets);
        device.finish();
    }
    map.timing.treeSeconds = since(t0);
    return map;
}

DeviceIrradianceMap uploadIrradiancePoints(Device& device, const std::vector<PclIrradiancePoint>& points,
                                           float minNormalCos, const std::vector<float>& cover,
                                           const std::vector<cl_float4>& nondirect) {
    if (!cover.empty() && cover.size() != points.size())
        throw InternalError("precomputed irradiance: " + std::to_string(cover.size()) + " covers for " +
                            std::to_string(points.size()) + " points");
    if (!nondirect.empty() && nondirect.size() != points.size())
        throw InternalError("precomputed irradiance: " + std::to_string(nondirect.size()) +
                            " nondirect irradiances for " + std::to_string(points.size()) + " points");
    const std::vector<float> unlimited(cover.empty() ? points.size() : 0, INFINITY);
    std::vector<cl_float4> whole;
    if (nondirect.empty())
        for (const PclIrradiancePoint& p : points) whole.push_back(cl_float4{{p.r, p.g, p.b, 0.0f}});
    return buildIrradianceTree(device, device.upload(points, CL_MEM_READ_WRITE),
                               device.upload(cover.empty() ? unlimited : cover, CL_MEM_READ_WRITE),
                               device.upload(nondirect.empty() ? whole : nondirect, CL_MEM_READ_WRITE), points.size(),
                               minNormalCos);
}

std::vector<PclIrradiancePoint> downloadIrradiancePoints(Device& device, const DeviceIrradianceMap& map) {
    return device.download<PclIrradiancePoint>(map.points, map.count);
}

std::vector<float> downloadIrradianceCover(Device& device, const DeviceIrradianceMap& map) {
    return device.download<float>(map.cover, map.count);
}

std::vector<float> downloadIrradianceNondirect(Device& device, const DeviceIrradianceMap& map) {
    return device.download<float>(map.nondirect, 4 * map.count);
}

double lookupIrradiance(Device& device, const DeviceIrradianceMap& map, const cl::Buffer& queries, size_t queryCount,
                        DeviceIrradianceLookup& out, bool zeroRadiusIsNone) {
    if (out.queries != queryCount || queryCount == 0) {
        out.irradiance = device.allocate<cl_float4>(queryCount, CL_MEM_READ_WRITE, "precomputed irradiance: lookups");
        out.chosen = device.allocate<uint32_t>(queryCount, CL_MEM_READ_WRITE, "precomputed irradiance: chosen points");
        out.queries = queryCount;
    }
    if (queryCount == 0) return 0.0;
    auto k = device.kernel<cl::Buffer, cl::Buffer, cl::Buffer, cl_uint, cl_uint, cl::Buffer, cl::Buffer, cl_uint,
                           cl_float, cl_uint, cl::Buffer, cl::Buffer>(kStage, "precomputed_irradiance_lookup");
    cl::Event e = device.launchLocal(kStage, k, wholeWorkGroups(queryCount), workGroup(), map.nodes, map.nodeCover,
                                     map.nodeNondirect, cl_uint(map.count), cl_uint(map.bucketFirst), map.buckets,
                                     queries, cl_uint(queryCount), cl_float(map.minNormalCos),
                                     cl_uint(zeroRadiusIsNone ? 1 : 0), out.irradiance, out.chosen);
    e.wait();
    return Device::elapsedSeconds(e);
}

}  // namespace pcl
