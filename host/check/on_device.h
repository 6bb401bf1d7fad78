// Device stages run on host vectors, for the checks and the tests: each function uploads its
// inputs, runs one stage of pipeline/ through its public API (the launches a render makes, with
// the same arguments) and downloads the result. Not in pipeline/: the production headers hold
// only what a render uses, and a render never starts from or ends in host vectors. Sections in
// pipeline order: the photon pass (emit, trace_photons, deposit), the photon maps (sort, kdtree,
// hashgrid, knn), the estimates (estimate, precomputed irradiance), the eye pass (intersect,
// camera rays, eye paths, direct light, final gather, eye estimate).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "pipeline/estimate.h"
#include "pipeline/final_gather.h"
#include "pipeline/hashgrid.h"
#include "pipeline/irradiance_source.h"
#include "pipeline/kdtree.h"
#include "pipeline/knn.h"
#include "pipeline/photon_pass.h"
#include "pipeline/precomputed_irradiance.h"
#include "prep/estimate_settings.h"
#include "prep/knn_structure.h"
#include "prep/scene_buffers.h"
#include "reference/eye_paths.h"
#include "shared/types.h"

namespace pcl {

// ---- emit (pipeline/emit.h) ----------------------------------------------------------------

// Emit alone, for checks and tests: upload, launch, download. params.batchSize rays.
std::vector<PclPhotonRay> emitOnDevice(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                       const std::vector<uint32_t>& lightFirst, const PclPhotonParams& params);

// ---- trace_photons (pipeline/trace_photons.h) ----------------------------------------------

struct PhotonTraceResult {
    uint32_t slotsPerPath = 0;
    std::vector<PclPhoton> slots;  // path-major (the twin's layout: slot k of path i at i*S + k, valid for
                                   // k < counts[i]), whatever the device's layout
    std::vector<uint32_t> counts;  // records deposited per path
    std::vector<uint32_t> ends;    // bounce | PCL_END_* << 8 per path
    // Volume photons (params.hasMedia; empty otherwise), path-major as slots.
    std::vector<PclPhoton> volumeSlots;
    std::vector<uint32_t> volumeCounts;
};

// Trace alone, for checks and tests: rays.size() must equal params.batchSize. Slots past a
// path's count are zeroed here (the kernel leaves them unwritten) so results compare byte-wise.
PhotonTraceResult tracePhotonsOnDevice(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                       const std::vector<PclPhotonRay>& rays, const PclPhotonParams& params);

// ---- deposit (pipeline/deposit.h) ----------------------------------------------------------

// Deposit alone, for checks and tests: counts.size() paths, slots.size() == paths × slotsPerPath,
// path-major as the twin writes them (uploaded slot-major, as the device keeps them).
// The map starts with `initialCapacity` records (0: exactly the total) and is downloaded.
std::vector<PclPhoton> depositOnDevice(Device& device, const std::vector<uint32_t>& counts,
                                       const std::vector<PclPhoton>& slots, uint32_t slotsPerPath,
                                       size_t initialCapacity = 0, uint32_t* growths = nullptr);

// The scan alone (tests).
std::vector<uint32_t> exclusiveScanOnDevice(Device& device, const std::vector<uint32_t>& values);

// ---- the photon pass (pipeline/photon_pass.h) -----------------------------------------------

// The maps the map and estimate checks read: a global and a caustic pass of `photons` paths
// each with `seed`; *seconds (optional) receives the wall time; causticTimes: also the caustic
// records' shutter times (PhotonPassOptions::causticTimes).
PhotonMaps photonMapsOnDevice(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                              uint32_t photons, uint64_t seed, double* seconds = nullptr, bool causticTimes = false);

// ---- sort (pipeline/sort.h) ----------------------------------------------------------------

// Order-preserving float → key flip on the device (sort_float_keys): keys[i] from x[i],
// values[i] = i.
void floatSortKeysOnDevice(Device& device, const std::vector<float>& x, std::vector<uint32_t>& keys,
                           std::vector<uint32_t>& values);

// ---- kdtree (pipeline/kdtree.h) ------------------------------------------------------------

struct KdTree {
    std::vector<PclPhoton> photons;  // heap order, axis bits set
    std::vector<uint32_t> index;     // heap position → input photon index
};

// Upload, build, download.
KdTree buildKdTreeOnDevice(Device& device, const std::vector<PclPhoton>& photons, KdTreeTiming* timing = nullptr,
                           int finishSize = -1);

// ---- hashgrid (pipeline/hashgrid.h) --------------------------------------------------------

// The grid's tables downloaded, for checks and tests.
struct HashGridTables {
    PclGridParams params{};
    std::vector<uint32_t> keys;                // hashes in sorted order
    std::vector<uint32_t> order;               // photon indices sorted by (hash, index)
    std::vector<uint32_t> cellStart, cellEnd;  // per hash; 0, 0 where empty
    std::vector<cl_float4> points;             // (x, y, z, photon index bits) in sorted order
};

HashGridTables hashGridOnDevice(Device& device, const std::vector<PclPhoton>& photons, float maxRadius,
                                HashGridBuild build = HashGridBuild::ForDevice);

// ---- knn (pipeline/knn.h) ------------------------------------------------------------------
//
//   std::vector<PclKnnQuery> qs = ...;              // x, y, z, maxRadius2, k (1..500)
//   KnnResult r = knnOnDevice(device, map, KnnStructure::HashGrid, qs);
//   for (uint32_t j = 0; j < r.counts[q]; ++j) use(r.indices[q * r.stride + j], r.dist2[q * r.stride + j]);

struct KnnResult {
    uint32_t stride = 0;            // slots per query: the largest k of the queries
    std::vector<uint32_t> counts;   // per query: neighbours found (≤ its k)
    std::vector<uint32_t> indices;  // queries × stride: photon indices, ascending (d², index); PCL_NO_HIT past count
    std::vector<float> dist2;       // queries × stride: squared distances; 0 past count
    std::vector<float> radius2;     // per query: the largest squared distance returned, 0 if none
    double searchSeconds = 0.0;     // device time of the search kernel
    double buildSeconds = 0.0;      // knnOnDevice: wall time to build the structure (upload included)
    size_t queries() const { return counts.size(); }
};

// A built structure searched for host queries in batches of knnQueryBatch, so no buffer passes
// the device's max allocation (capped or not): per batch upload, search, download. The same
// bits as one launch. searchSeconds sums the launches; buildSeconds is left 0. The hash grid
// needs every radius ≤ cellSize / 2 (the caller checks).
KnnResult knnSearchOnDevice(Device& device, const KnnKdTree& tree, const std::vector<PclKnnQuery>& queries);
KnnResult knnSearchOnDevice(Device& device, const DeviceHashGrid& grid, const std::vector<PclKnnQuery>& queries);

// Host-side conveniences: upload, search, download.
KnnResult knnKdTreeOnDevice(Device& device, const std::vector<PclPhoton>& heapNodes,
                            const std::vector<uint32_t>& nodeIndex, const std::vector<PclKnnQuery>& queries);
// Builds the grid for r_max = the largest query radius, then searches.
KnnResult knnHashGridOnDevice(Device& device, const std::vector<PclPhoton>& map,
                              const std::vector<PclKnnQuery>& queries);

// The whole thing from a photon map in deposit order: builds the structure on the device
// (buildKdTree, or buildHashGrid for r_max = the largest query radius) and searches. Indices
// refer to `map`.
KnnResult knnOnDevice(Device& device, const std::vector<PclPhoton>& map, KnnStructure structure,
                      const std::vector<PclKnnQuery>& queries);

// ---- estimate (pipeline/estimate.h) --------------------------------------------------------
//
//   PhotonMapOnDevice map(device, photons, KnnStructure::KdTree, rMax);  // built once
//   EstimateResult e = estimateOnDevice(device, map, queries, settings, &deviceScene);
//   e.values[q].r, .g, .b (W/m²), .used, .radius2

struct EstimateResult {
    std::vector<PclEstimate> values;  // per query: irradiance rgb (W/m²), radius2, used, found
    EstimateTiming timing;
    double buildSeconds = 0.0;  // estimateOnDevice: the structure's build (upload included)
    size_t queries() const { return values.size(); }
};

// Upload, estimate, download on a map already built.
EstimateResult estimateOnDevice(Device& device, const PhotonMapOnDevice& map,
                                const std::vector<PclEstimateQuery>& queries, const EstimateSettings& settings,
                                const DeviceScene* sceneForVisibility);

// The whole thing from a map in deposit order: builds settings.structure (the hash grid for the
// largest query radius) and estimates.
EstimateResult estimateOnDevice(Device& device, const std::vector<PclPhoton>& map,
                                const std::vector<PclEstimateQuery>& queries, const EstimateSettings& settings,
                                const DeviceScene* sceneForVisibility);

// ---- precomputed irradiance (pipeline/precomputed_irradiance.h) ----------------------------

struct IrradianceLookupResult {
    std::vector<float> irradiance;  // queries × 4: r, g, b, d²
    std::vector<uint32_t> chosen;   // per query
    double seconds = 0.0;           // device time of the lookup kernel
};

// Upload the queries, look up, download. InternalError when a radius is negative or NaN or a
// normal is not finite.
IrradianceLookupResult lookupIrradianceOnDevice(Device& device, const DeviceIrradianceMap& map,
                                                const std::vector<PclEstimateQuery>& queries);

// ---- intersect (pipeline/intersect.h) ------------------------------------------------------

// Convenience for tests and checks: upload, trace, download.
std::vector<PclHit> intersectOnDevice(Device& device, const SceneGeometry& geometry, const std::vector<PclRay>& rays,
                                      bool anyHit);

// ---- camera rays (pipeline/camera_rays.h) --------------------------------------------------

// For tests: one launch over params' range, downloaded.
std::vector<PclRay> cameraRaysOnDevice(Device& device, const PclCameraParams& params);

// ---- eye paths (pipeline/eye_paths.h) ------------------------------------------------------

// For tests: upload rays (rays.size() == params.sampleCount), trace, download; the medium
// segments (scenes with media, params.volumeSegments > 0) into *segments when given.
std::vector<PclEyeHit> eyePathsOnDevice(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                        const std::vector<PclRay>& rays, const PclEyeParams& params,
                                        EyeVolumeSegments* segments = nullptr);

// ---- direct light (pipeline/direct_light.h) ------------------------------------------------

// For tests: upload, run, download (histograms: the tables when params.histogramCells > 0).
std::vector<PclRadiance> directLightOnDevice(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                             const std::vector<PclEyeHit>& hits, const PclDirectParams& params,
                                             const std::vector<float>* histograms = nullptr);

// ---- final gather (pipeline/final_gather.h) ------------------------------------------------

struct GatherResult {
    std::vector<PclEstimateQuery> queries;  // sampleCount × N
    std::vector<PclGatherHit> gathered;     // sampleCount × N
    std::vector<PclRadiance> radiance;      // sampleCount
    GatherTiming timing;
};
// For tests: upload, run, download everything.
// With params.histogramCells > 0 the tables are built from `global` (required then), and
// downloaded into `histograms` when given.
GatherResult finalGatherOnDevice(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                 const std::vector<PclEyeHit>& hits, const PclGatherParams& params,
                                 IrradianceSource& source, const PhotonMapOnDevice* global = nullptr,
                                 std::vector<float>* histograms = nullptr);

// ---- eye estimate (pipeline/eye_estimate.h) ------------------------------------------------

// For tests: upload the hits, run, download queries and radiance.
struct EyeEstimateResult {
    std::vector<PclEstimateQuery> queries;
    std::vector<PclRadiance> radiance;
};
// primInfo: the scene's primitives, needed with params.atShutterOpen (InternalError without).
EyeEstimateResult estimateAtEyeHitsOnDevice(Device& device, const std::vector<PclEyeHit>& hits,
                                            const PclEyeEstimateParams& params, IrradianceSource& source,
                                            const std::vector<PclPrimInfo>& primInfo = {});

}  // namespace pcl
