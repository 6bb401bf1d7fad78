// The irradiance estimate on the device (kernels/estimate.cl; kernels/README.md, "estimate";
// Jensen 2001 §7.2): per query, the k nearest photons (pipeline/knn) and
//   E = Σ_p w(d_p/r) ΔΦ_p / (norm · π r²),   r² = the kNN's squared distance to its k-th photon,
// summed in the kNN's (d², index) order, over the photons that pass the rejection tests: the
// photon arrived from the shaded side (w_p·n_q > 0), its surface faces the same way
// (n_p·n_q ≥ minNormalCos) and, with `visibility`, nothing lies between the lifted query and
// the lifted photon (thin walls whose floors are coplanar on both sides pass the normal tests).
// The CPU twin is host/reference/estimate.h.
//
//   PhotonMapOnDevice map(device, photons, KnnStructure::KdTree, rMax);  // built once
//   estimateBuffers(device, map, queryBuffer, n, maxK, settings, &deviceScene, resultBuffer);
//   // resultBuffer: PclEstimate[n], .r, .g, .b (W/m²), .used, .radius2
//
// Host vectors in and out, for the checks and the tests: estimateOnDevice in check/on_device.h.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "pipeline/device_scene.h"
#include "pipeline/hashgrid.h"
#include "pipeline/knn.h"
#include "prep/estimate_settings.h"
#include "shared/types.h"

namespace pcl {

// A photon map on the device (records in map order: kNN indices refer to them) with its search
// structure, built once and searched by any number of estimate batches.
class PhotonMapOnDevice {
public:
    // Uploads `map` and builds `structure`. maxRadius: the largest search radius any query will
    // ask (the hash grid's cells are 2 maxRadius; queries above it are an InternalError there);
    // the kd-tree ignores it.
    PhotonMapOnDevice(Device& device, const std::vector<PclPhoton>& map, KnnStructure structure, float maxRadius);
    // A map already on the device: `photons` holds `count` records in map order. The hash grid
    // needs the map's bounds minimum `lo` (its origin; every photon ≥ lo).
    PhotonMapOnDevice(Device& device, const cl::Buffer& photons, size_t count, KnnStructure structure, float maxRadius,
                      const float lo[3]);

    KnnStructure structure() const { return structure_; }
    size_t size() const { return count_; }
    float maxRadius() const { return maxRadius_; }
    const cl::Buffer& photons() const { return photons_; }
    double buildSeconds() const { return buildSeconds_; }  // wall time: upload and structure build

    // The kNN search of `queryCount` PclKnnQuery in `queries` (stride maxK) into `out`; returns
    // the kernel's device seconds.
    double search(Device& device, const cl::Buffer& queries, size_t queryCount, uint32_t maxK, DeviceKnnOutput& out,
                  float firstRadius2 = INFINITY) const;

private:
    void build(Device& device, const float lo[3]);
    KnnStructure structure_;
    size_t count_ = 0;
    float maxRadius_ = 0.0f;
    cl::Buffer photons_;
    KnnKdTree tree_;
    DeviceHashGrid grid_;
    double buildSeconds_ = 0.0;
};

struct EstimateTiming {
    double knnSeconds = 0.0;       // device time of the kNN searches
    double estimateSeconds = 0.0;  // device time of the estimate kernels (query conversion included)
    size_t batches = 0;
    size_t batchQueries = 0;  // queries per batch (the last may hold fewer)
};

// Queries per batch so the kNN's index and distance buffers (queries × maxK × 8 bytes) stay
// within a quarter of device.info().maxAlloc (at least 1, at most 2^20).
size_t estimateBatchQueries(const Device& device, uint32_t maxK);

// The estimates of `queryCount` PclEstimateQuery in `queries` into `results` (PclEstimate[
// queryCount], allocated by the caller), in batches of estimateBatchQueries. maxK ≥ every
// query's k (a larger k is clamped to maxK); each k in 1..PCL_KNN_MAX_K. With the hash grid a
// query radius above the map's maxRadius is clamped to it. `scene` is required when
// settings.visibility is on (InternalError otherwise) and ignored when off; its programOptions()
// size the traversal stack. settings.structure is ignored (the map's is used). Enqueues and
// waits for the launches.
EstimateTiming estimateBuffers(Device& device, const PhotonMapOnDevice& map, const cl::Buffer& queries,
                               size_t queryCount, uint32_t maxK, const EstimateSettings& settings,
                               const DeviceScene* scene, cl::Buffer& results);

}  // namespace pcl
