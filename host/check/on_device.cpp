#include "check/on_device.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <string>

#include "core/clock.h"
#include "core/error.h"
#include "device/work_group.h"
#include "pipeline/camera_rays.h"
#include "pipeline/deposit.h"
#include "pipeline/device_scene.h"
#include "pipeline/direct_light.h"
#include "pipeline/emit.h"
#include "pipeline/eye_estimate.h"
#include "pipeline/eye_paths.h"
#include "pipeline/intersect.h"
#include "pipeline/photon_pass.h"
#include "pipeline/trace_photons.h"
#include "prep/area_light_table.h"

namespace pcl {

// ---- emit ---------------------------------------------------------------------------------------

std::vector<PclPhotonRay> emitOnDevice(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                       const std::vector<uint32_t>& lightFirst, const PclPhotonParams& params) {
    DeviceScene scene(device, geometry, buffers);
    cl::Buffer first = device.upload(lightFirst, CL_MEM_READ_ONLY, "photon pass: light offsets");
    cl::Buffer rays = device.allocate<PclPhotonRay>(params.batchSize, CL_MEM_READ_WRITE, "photon pass: rays");
    emitPhotons(device, scene, first, params, rays);
    return device.download<PclPhotonRay>(rays, params.batchSize);
}

// ---- trace_photons ------------------------------------------------------------------------------

PhotonTraceResult tracePhotonsOnDevice(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                       const std::vector<PclPhotonRay>& rays, const PclPhotonParams& params) {
    if (rays.size() != params.batchSize)
        throw InternalError("tracePhotonsOnDevice: " + std::to_string(rays.size()) + " rays for a batch of " +
                            std::to_string(params.batchSize));
    DeviceScene scene(device, geometry, buffers);
    PhotonTraceResult r;
    r.slotsPerPath = photonSlotsPerPath(params);
    const size_t n = params.batchSize, S = r.slotsPerPath;
    r.slots.resize(n * S);
    r.counts.resize(n);
    r.ends.resize(n);
    const bool media = params.hasMedia != 0;
    if (media) {
        r.volumeSlots.resize(n * S);
        r.volumeCounts.resize(n);
    }
    // In launches of at most a pass's batch, so a large check neither outgrows a buffer nor
    // runs one long launch; photon indices (and so the random numbers) are unchanged.
    const size_t chunk =
        std::min<size_t>(std::max<size_t>(n, 1), defaultPhotonBatch(device, uint32_t(S) * (media ? 2u : 1u)));
    cl::Buffer rayBuf = device.allocate<PclPhotonRay>(chunk, CL_MEM_READ_WRITE, "photon pass: rays");
    cl::Buffer slots = device.allocate<PclPhoton>(chunk * S, CL_MEM_READ_WRITE, "photon pass: slots");
    cl::Buffer counts = device.allocate<uint32_t>(chunk, CL_MEM_READ_WRITE, "photon pass: counts");
    cl::Buffer ends = device.allocate<uint32_t>(chunk, CL_MEM_READ_WRITE, "photon pass: ends");
    cl::Buffer volumeSlots =
        device.allocate<PclPhoton>(media ? chunk * S : 1, CL_MEM_READ_WRITE, "photon pass: volume slots");
    cl::Buffer volumeCounts =
        device.allocate<uint32_t>(media ? chunk : 1, CL_MEM_READ_WRITE, "photon pass: volume counts");
    for (size_t first = 0; first < n; first += chunk) {
        const size_t m = std::min(chunk, n - first);
        Device::guard("upload", [&] {
            device.queue().enqueueWriteBuffer(rayBuf, CL_TRUE, 0, m * sizeof(PclPhotonRay), rays.data() + first);
        });
        PclPhotonParams p = params;
        p.firstPhoton = params.firstPhoton + uint32_t(first);
        p.batchSize = uint32_t(m);
        tracePhotons(device, scene, p, rayBuf, slots, counts, ends, volumeSlots, volumeCounts);
        std::vector<PclPhoton> chunkSlots(m * S);  // slot-major: record k of path p at k*m + p
        if (media) {
            std::vector<PclPhoton> chunkVolume(m * S);
            Device::guard("download", [&] {
                device.queue().enqueueReadBuffer(volumeSlots, CL_TRUE, 0, m * S * sizeof(PclPhoton),
                                                 chunkVolume.data());
                device.queue().enqueueReadBuffer(volumeCounts, CL_TRUE, 0, m * sizeof(uint32_t),
                                                 r.volumeCounts.data() + first);
            });
            const std::vector<PclPhoton> v = pathMajor(chunkVolume, m, uint32_t(S));
            std::copy(v.begin(), v.end(), r.volumeSlots.begin() + first * S);
        }
        Device::guard("download", [&] {
            device.queue().enqueueReadBuffer(slots, CL_TRUE, 0, m * S * sizeof(PclPhoton), chunkSlots.data());
            device.queue().enqueueReadBuffer(counts, CL_TRUE, 0, m * sizeof(uint32_t), r.counts.data() + first);
            device.queue().enqueueReadBuffer(ends, CL_TRUE, 0, m * sizeof(uint32_t), r.ends.data() + first);
        });
        const std::vector<PclPhoton> chunkPathMajor = pathMajor(chunkSlots, m, uint32_t(S));
        std::copy(chunkPathMajor.begin(), chunkPathMajor.end(), r.slots.begin() + first * S);
    }
    for (size_t i = 0; i < n; ++i)
        for (uint32_t k = r.counts[i]; k < S; ++k) r.slots[i * S + k] = PclPhoton{};
    if (media)
        for (size_t i = 0; i < n; ++i)
            for (uint32_t k = r.volumeCounts[i]; k < S; ++k) r.volumeSlots[i * S + k] = PclPhoton{};
    return r;
}

// ---- deposit ------------------------------------------------------------------------------------

std::vector<PclPhoton> depositOnDevice(Device& device, const std::vector<uint32_t>& counts,
                                       const std::vector<PclPhoton>& slots, uint32_t slotsPerPath,
                                       size_t initialCapacity, uint32_t* growths) {
    if (slots.size() != counts.size() * size_t(slotsPerPath))
        throw InternalError("depositOnDevice: " + std::to_string(slots.size()) + " slots for " +
                            std::to_string(counts.size()) + " paths of " + std::to_string(slotsPerPath));
    for (size_t i = 0; i < counts.size(); ++i)
        if (counts[i] > slotsPerPath)
            throw InternalError("depositOnDevice: path " + std::to_string(i) + " claims " + std::to_string(counts[i]) +
                                " records in " + std::to_string(slotsPerPath) + " slots");
    const uint64_t total = std::accumulate(counts.begin(), counts.end(), uint64_t(0));
    DevicePhotonMap map = makeDevicePhotonMap(device, initialCapacity ? initialCapacity : size_t(total));
    // All paths in one deposit when their slots fit one buffer; else in chunks of paths that do
    // (a --max-buffer-mib cap): appended in path order, so the map is the same.
    const size_t n = counts.size(), S = std::max<uint32_t>(slotsPerPath, 1);
    size_t chunk = std::max<size_t>(n, 1);
    if (chunk * S * sizeof(PclPhoton) > device.info().maxAlloc)
        chunk = std::max<size_t>(device.info().maxAlloc / (S * sizeof(PclPhoton)), 1);
    for (size_t first = 0; first < n; first += chunk) {
        const size_t m = std::min(chunk, n - first);
        cl::Buffer countBuf = device.upload(std::vector<uint32_t>(counts.begin() + first, counts.begin() + first + m),
                                            CL_MEM_READ_ONLY, "photon pass: counts");
        cl::Buffer slotBuf =
            device.upload(slotMajor(std::vector<PclPhoton>(slots.begin() + first * S, slots.begin() + (first + m) * S),
                                    m, uint32_t(S)),
                          CL_MEM_READ_ONLY, "photon pass: slots");
        depositPhotons(device, countBuf, slotBuf, uint32_t(m), map);
    }
    if (growths) *growths = map.growths;
    return device.download<PclPhoton>(map.photons, map.count);
}

PhotonMaps photonMapsOnDevice(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                              uint32_t photons, uint64_t seed, double* seconds, bool causticTimes) {
    PhotonPassOptions po;
    po.causticTimes = causticTimes;
    po.globalPhotons = photons;
    po.causticPhotons = photons;
    po.seed = seed;
    const auto t0 = Clock::now();
    PhotonMaps maps = runPhotonPass(device, geometry, buffers, po);
    if (seconds) *seconds = since(t0);
    return maps;
}

std::vector<uint32_t> exclusiveScanOnDevice(Device& device, const std::vector<uint32_t>& values) {
    if (values.empty()) return {};
    cl::Buffer in = device.upload(values);
    cl::Buffer out = device.allocate<uint32_t>(values.size());
    exclusiveScan(device, in, out, values.size());
    return device.download<uint32_t>(out, values.size());
}

// ---- sort ---------------------------------------------------------------------------------------

void floatSortKeysOnDevice(Device& device, const std::vector<float>& x, std::vector<uint32_t>& keys,
                           std::vector<uint32_t>& values) {
    const size_t n = x.size();
    cl::Buffer in = device.upload(x);
    cl::Buffer k = device.allocate<uint32_t>(n), v = device.allocate<uint32_t>(n);
    auto flip = device.kernel<cl::Buffer, cl_uint, cl::Buffer, cl::Buffer>("sort", "sort_float_keys");
    device.launchLocal("sort", flip, wholeWorkGroups(n), workGroup(), in, cl_uint(n), k, v);
    keys = device.download<uint32_t>(k, n);
    values = device.download<uint32_t>(v, n);
}

// ---- kdtree -------------------------------------------------------------------------------------

KdTree buildKdTreeOnDevice(Device& device, const std::vector<PclPhoton>& photons, KdTreeTiming* timing,
                           int finishSize) {
    cl::Buffer in = device.upload(photons, CL_MEM_READ_ONLY, "kd-tree: photons");
    DeviceKdTree t = buildKdTree(device, in, photons.size(), timing, finishSize);
    KdTree out;
    out.photons = device.download<PclPhoton>(t.photons, t.count);
    out.index = device.download<uint32_t>(t.index, t.count);
    return out;
}

// ---- hashgrid -----------------------------------------------------------------------------------

HashGridTables hashGridOnDevice(Device& device, const std::vector<PclPhoton>& photons, float maxRadius,
                                HashGridBuild build) {
    HashGridTables t;
    t.params = hashGridParams(photons, maxRadius);
    cl::Buffer buf = device.upload(photons, CL_MEM_READ_ONLY, "hash grid: photons");
    DeviceHashGrid g = buildHashGrid(device, buf, photons.size(), t.params, build);
    t.keys = device.download<uint32_t>(g.keys, g.count);
    t.order = device.download<uint32_t>(g.order, g.count);
    t.cellStart = device.download<uint32_t>(g.cellStart, t.params.tableSize);
    t.cellEnd = device.download<uint32_t>(g.cellEnd, t.params.tableSize);
    t.points = device.download<cl_float4>(g.points, g.count);
    return t;
}

// ---- knn ----------------------------------------------------------------------------------------

namespace {

// The common tail of the knn*OnDevice calls, once the structure is built: in batches of
// knnQueryBatch queries (so no output buffer passes the device's max allocation, capped or
// not), uploads the batch, runs `search(queryBuffer, count, out)` (one search launch, returning
// its device seconds) and downloads it into its place. Queries are independent, so the result is
// the same bits whatever the batch.
template <class Search>
KnnResult searchAndDownload(Device& device, const std::vector<PclKnnQuery>& queries, uint32_t maxK, double buildSeconds,
                            Search search) {
    const size_t n = queries.size();
    const size_t batch =
        std::min(std::max<size_t>(n, 1), knnQueryBatch(device.info().maxAlloc, device.info().globalMem, maxK));
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
        throw InternalError("knn: " + std::to_string(heapNodes.size()) + " kd-tree nodes with " +
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

KnnResult knnHashGridOnDevice(Device& device, const std::vector<PclPhoton>& map,
                              const std::vector<PclKnnQuery>& queries) {
    const uint32_t maxK = knnMaxK(queries);
    float maxRadius2 = 0.0f;
    for (const PclKnnQuery& q : queries) maxRadius2 = std::max(maxRadius2, q.maxRadius2);
    if (!std::isfinite(maxRadius2))
        throw InternalError("knn: the hash grid needs a finite search radius (a query has maxRadius2 = inf)");
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

// ---- estimate -----------------------------------------------------------------------------------

namespace {

float largestRadius(const std::vector<PclEstimateQuery>& queries) {
    float maxRadius2 = 0.0f;
    for (const PclEstimateQuery& q : queries) maxRadius2 = std::max(maxRadius2, q.maxRadius2);
    if (!std::isfinite(maxRadius2))
        throw InternalError("estimate: the hash grid needs a finite search radius (a query has maxRadius2 = inf)");
    const float r = std::sqrt(maxRadius2);
    return r > 0.0f ? r : 1.0f;  // every radius 0: any cell size finds the photons at the query
}

}  // namespace

EstimateResult estimateOnDevice(Device& device, const PhotonMapOnDevice& map,
                                const std::vector<PclEstimateQuery>& queries, const EstimateSettings& settings,
                                const DeviceScene* sceneForVisibility) {
    const uint32_t maxK = estimateMaxK(queries);
    if (map.structure() == KnnStructure::HashGrid)
        for (size_t i = 0; i < queries.size(); ++i)
            if (!(std::sqrt(queries[i].maxRadius2) <= map.maxRadius()))
                throw InternalError("estimate: query " + std::to_string(i) + " has radius " +
                                    std::to_string(std::sqrt(queries[i].maxRadius2)) +
                                    ", above the hash grid's maxRadius " + std::to_string(map.maxRadius()));
    EstimateResult r;
    cl::Buffer q = device.upload(queries, CL_MEM_READ_ONLY, "estimate: queries");
    cl::Buffer out = device.allocate<PclEstimate>(queries.size(), CL_MEM_READ_WRITE, "estimate: results");
    r.timing = estimateBuffers(device, map, q, queries.size(), maxK, settings, sceneForVisibility, out);
    r.values = device.download<PclEstimate>(out, queries.size());
    r.buildSeconds = map.buildSeconds();
    return r;
}

EstimateResult estimateOnDevice(Device& device, const std::vector<PclPhoton>& map,
                                const std::vector<PclEstimateQuery>& queries, const EstimateSettings& settings,
                                const DeviceScene* sceneForVisibility) {
    estimateMaxK(queries);
    validateEstimateSettings(settings);
    const float rMax = settings.structure == KnnStructure::HashGrid ? largestRadius(queries) : 0.0f;
    const PhotonMapOnDevice built(device, map, settings.structure, rMax);
    return estimateOnDevice(device, built, queries, settings, sceneForVisibility);
}

// ---- precomputed irradiance ---------------------------------------------------------------------

IrradianceLookupResult lookupIrradianceOnDevice(Device& device, const DeviceIrradianceMap& map,
                                                const std::vector<PclEstimateQuery>& queries) {
    for (size_t i = 0; i < queries.size(); ++i) {
        const PclEstimateQuery& q = queries[i];
        if (!(q.maxRadius2 >= 0.0f))
            throw InternalError("precomputed irradiance: query " + std::to_string(i) +
                                " has maxRadius2 = " + std::to_string(q.maxRadius2) + ", expected ≥ 0");
        if (!std::isfinite(q.nx) || !std::isfinite(q.ny) || !std::isfinite(q.nz))
            throw InternalError("precomputed irradiance: query " + std::to_string(i) + " has a non-finite normal");
    }
    IrradianceLookupResult r;
    cl::Buffer q = device.upload(queries);
    DeviceIrradianceLookup out;
    r.seconds = lookupIrradiance(device, map, q, queries.size(), out);
    r.irradiance = device.download<float>(out.irradiance, queries.size() * 4);
    r.chosen = device.download<uint32_t>(out.chosen, queries.size());
    return r;
}

// ---- intersect ----------------------------------------------------------------------------------

std::vector<PclHit> intersectOnDevice(Device& device, const SceneGeometry& geometry, const std::vector<PclRay>& rays,
                                      bool anyHit) {
    DeviceGeometry dg(device, geometry);
    cl::Buffer rayBuf = device.upload(rays, CL_MEM_READ_ONLY, "intersect: rays");
    cl::Buffer hitBuf = device.allocate<PclHit>(rays.size(), CL_MEM_WRITE_ONLY, "intersect: hits");
    intersectBuffers(device, dg, rayBuf, hitBuf, rays.size(), anyHit);
    return device.download<PclHit>(hitBuf, rays.size());
}

// ---- camera rays --------------------------------------------------------------------------------

std::vector<PclRay> cameraRaysOnDevice(Device& device, const PclCameraParams& params) {
    cl::Buffer rays = device.allocate<PclRay>(params.sampleCount, CL_MEM_READ_WRITE, "camera: rays");
    generateCameraRays(device, params, rays);
    return device.download<PclRay>(rays, params.sampleCount);
}

// ---- eye paths ----------------------------------------------------------------------------------

std::vector<PclEyeHit> eyePathsOnDevice(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                        const std::vector<PclRay>& rays, const PclEyeParams& params,
                                        EyeVolumeSegments* segments) {
    if (rays.size() != params.sampleCount)
        throw InternalError("eyePathsOnDevice: " + std::to_string(rays.size()) + " rays for " +
                            std::to_string(params.sampleCount) + " samples");
    DeviceScene scene(device, geometry, buffers);
    const DeviceAreaLights lights(device, buildAreaLightTable(buffers, geometry.primitiveCount()));
    cl::Buffer rayBuf = device.upload(rays, CL_MEM_READ_ONLY, "eye paths: rays");
    cl::Buffer hits = device.allocate<PclEyeHit>(rays.size(), CL_MEM_READ_WRITE, "eye paths: hits");
    const size_t n = rays.size(), S = params.volumeSegments;
    cl::Buffer segBuf =
        device.allocate<PclVolumeSegment>(std::max<size_t>(1, S * n), CL_MEM_READ_WRITE, "eye paths: segments");
    cl::Buffer countBuf = device.allocate<uint32_t>(S > 0 ? n : 1, CL_MEM_READ_WRITE, "eye paths: segment counts");
    traceEyePaths(device, scene, lights, params, rayBuf, hits, segBuf, countBuf);
    std::vector<PclEyeHit> out = device.download<PclEyeHit>(hits, n);
    if (segments) {
        segments->perRecord = params.volumeSegments;
        segments->segments = S > 0 ? device.download<PclVolumeSegment>(segBuf, S * n) : std::vector<PclVolumeSegment>{};
        segments->counts = S > 0 ? device.download<uint32_t>(countBuf, n) : std::vector<uint32_t>(n, 0);
    }
    return out;
}

// ---- direct light -------------------------------------------------------------------------------

std::vector<PclRadiance> directLightOnDevice(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                             const std::vector<PclEyeHit>& hits, const PclDirectParams& params,
                                             const std::vector<float>* histograms) {
    if (hits.size() != params.sampleCount)
        throw InternalError("directLightOnDevice: " + std::to_string(hits.size()) + " records for " +
                            std::to_string(params.sampleCount));
    const size_t cells = size_t(params.histogramCells) * params.histogramCells;
    if (cells > 0 && (!histograms || histograms->size() != hits.size() * cells))
        throw InternalError("directLightOnDevice: histogramCells " + std::to_string(params.histogramCells) +
                            " needs records × G² histogram entries");
    DeviceScene scene(device, geometry, buffers);
    DeviceAreaLights lights(device, buildAreaLightTable(buffers, geometry.primitiveCount()));
    cl::Buffer hitBuf = device.upload(hits, CL_MEM_READ_ONLY, "direct light: eye hits");
    cl::Buffer hist = cells > 0 ? device.upload(*histograms, CL_MEM_READ_ONLY, "direct light: histograms")
                                : device.allocate<float>(1, CL_MEM_READ_ONLY, "direct light: no histograms");
    cl::Buffer out = device.allocate<PclRadiance>(hits.size(), CL_MEM_READ_WRITE, "direct light: radiance");
    directLight(device, scene, lights, params, hitBuf, hist, out);
    return device.download<PclRadiance>(out, hits.size());
}

// ---- final gather -------------------------------------------------------------------------------

GatherResult finalGatherOnDevice(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                 const std::vector<PclEyeHit>& hits, const PclGatherParams& params,
                                 IrradianceSource& source, const PhotonMapOnDevice* global,
                                 std::vector<float>* histogramsOut) {
    if (hits.size() != params.sampleCount)
        throw InternalError("finalGatherOnDevice: " + std::to_string(hits.size()) + " records for " +
                            std::to_string(params.sampleCount));
    DeviceScene scene(device, geometry, buffers);
    DeviceAreaLights lights(device, buildAreaLightTable(buffers, geometry.primitiveCount()));
    PclGatherParams p = params;
    p.irradianceStride = source.strideFloats;
    const size_t n = size_t(p.sampleCount) * p.gatherRays;  // gather rays: sampleCount × N
    cl::Buffer hitBuf = device.upload(hits, CL_MEM_READ_ONLY, "final gather: eye hits");
    cl::Buffer queries = device.allocate<PclEstimateQuery>(n, CL_MEM_READ_WRITE, "final gather: queries");
    cl::Buffer gathered = device.allocate<PclGatherHit>(n, CL_MEM_READ_WRITE, "final gather: gathered rays");
    cl::Buffer radiance = device.allocate<PclRadiance>(hits.size(), CL_MEM_READ_WRITE, "final gather: radiance");
    GatherResult r;
    cl::Buffer histograms = device.allocate<float>(1, CL_MEM_READ_ONLY, "final gather: no histograms");
    if (p.histogramCells > 0) {
        if (!global) throw InternalError("finalGatherOnDevice: histogramCells > 0 needs the global map");
        histograms = buildGatherHistograms(device, *global, p, hitBuf);
        if (histogramsOut)
            *histogramsOut = device.download<float>(histograms, hits.size() * p.histogramCells * p.histogramCells);
    }
    cl::Event e = traceGatherRays(device, scene, lights, p, hitBuf, histograms, queries, gathered);
    device.finish();
    if (e()) r.timing.traceSeconds = Device::elapsedSeconds(e);
    const double before = source.seconds;
    cl::Buffer irradiance = source.evaluate(device, queries, n);
    r.timing.irradianceSeconds = source.seconds - before;
    e = resolveGather(device, p, hitBuf, gathered, irradiance, radiance);
    device.finish();
    if (e()) r.timing.resolveSeconds = Device::elapsedSeconds(e);
    r.queries = device.download<PclEstimateQuery>(queries, n);
    r.gathered = device.download<PclGatherHit>(gathered, n);
    r.radiance = device.download<PclRadiance>(radiance, hits.size());
    return r;
}

// ---- eye estimate -------------------------------------------------------------------------------

EyeEstimateResult estimateAtEyeHitsOnDevice(Device& device, const std::vector<PclEyeHit>& hits,
                                            const PclEyeEstimateParams& params, IrradianceSource& source,
                                            const std::vector<PclPrimInfo>& primInfo) {
    if (hits.size() != params.sampleCount)
        throw InternalError("estimateAtEyeHitsOnDevice: " + std::to_string(hits.size()) + " records for " +
                            std::to_string(params.sampleCount));
    validateEyeEstimateParams(params);
    if (params.atShutterOpen && primInfo.empty())
        throw InternalError("estimateAtEyeHitsOnDevice: atShutterOpen without the scene's primitives");
    PclEyeEstimateParams p = params;
    p.irradianceStride = source.strideFloats;
    cl::Buffer hitBuf = device.upload(hits, CL_MEM_READ_ONLY, "eye estimate: eye hits");
    cl::Buffer queries = device.allocate<PclEstimateQuery>(hits.size(), CL_MEM_READ_WRITE, "eye estimate: queries");
    cl::Buffer radiance = device.allocate<PclRadiance>(hits.size(), CL_MEM_READ_WRITE, "eye estimate: radiance");
    // A kernel argument even where it is not read (atShutterOpen 0): one placeholder record.
    cl::Buffer prims = device.upload(primInfo.empty() ? std::vector<PclPrimInfo>(1) : primInfo, CL_MEM_READ_ONLY,
                                     "eye estimate: primitives");
    eyeEstimateQueries(device, p, hitBuf, prims, queries);
    cl::Buffer irradiance = source.evaluate(device, queries, hits.size());
    eyeEstimateResolve(device, p, hitBuf, irradiance, radiance);
    EyeEstimateResult r;
    r.queries = device.download<PclEstimateQuery>(queries, hits.size());
    r.radiance = device.download<PclRadiance>(radiance, hits.size());
    return r;
}

}  // namespace pcl
