// k nearest photons on the device (kernels/knn.cl; kernels/README.md, "Photon maps", knn): per
// query the k photons nearest a point within its maximum radius, through the left-balanced
// kd-tree or the hash grid, a bounded max-heap per query with ties in distance broken by the
// lower photon index. Both structures return exactly what the brute force
// (host/reference/knn.cpp) returns: the same indices in the same order and the same squared
// distances.
//
//   std::vector<PclKnnQuery> qs = ...;              // x, y, z, maxRadius2, k (1..500)
//   KnnResult r = knnOnDevice(device, map, KnnStructure::HashGrid, qs);
//   for (uint32_t j = 0; j < r.counts[q]; ++j) use(r.indices[q * r.stride + j], r.dist2[q * r.stride + j]);
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "pipeline/hashgrid.h"
#include "pipeline/kdtree.h"
#include "prep/knn_structure.h"
#include "shared/types.h"

namespace pcl {

struct KnnResult {
    uint32_t stride = 0;              // slots per query: the largest k of the queries
    std::vector<uint32_t> counts;     // per query: neighbours found (≤ its k)
    std::vector<uint32_t> indices;    // queries × stride: photon indices, ascending (d², index); PCL_NO_HIT past count
    std::vector<float> dist2;         // queries × stride: squared distances; 0 past count
    std::vector<float> radius2;       // per query: the largest squared distance returned, 0 if none
    double searchSeconds = 0.0;       // device time of the search kernel
    double buildSeconds = 0.0;        // knnOnDevice: wall time to build the structure (upload included)
    size_t queries() const { return counts.size(); }
};

// The search kernels' outputs on the device.
struct DeviceKnnOutput {
    cl::Buffer counts, indices, dist2, radius2;
    uint32_t stride = 0;
    size_t queries = 0;
};

// A kd-tree ready for the search: buildKdTree's nodes packed as float4 (x, y, z, photon index
// | split axis << 30 as the bits of w), one load per visited node (knn_pack_kdtree).
struct KnnKdTree {
    cl::Buffer nodes;
    size_t count = 0;
};
// InputError for trees of 2^30 photons or more (the index field).
KnnKdTree packKdTree(Device& device, const DeviceKdTree& tree);

// Heap capacity the kernel is specialised for (-DPCL_KNN_CAP): the smallest of 8, 32, 64, 128,
// 256, 500 holding maxK. InputError outside 1..PCL_KNN_MAX_K.
uint32_t knnHeapCapacity(uint32_t maxK);

// Queries per search launch for the *OnDevice conveniences (and the memory plan): as many as
// keep every buffer of the batch (queries 32 B, indices and dist2 4·maxK B each per query) under
// maxAlloc and the batch's buffers together under a quarter of globalMem; whole work-groups of
// 64. A smaller maxAlloc (--max-buffer-mib) only splits the work: the results are the same.
size_t knnQueryBatch(size_t maxAlloc, size_t globalMem, uint32_t maxK);

// The searches on structures and queries already on the device (the kd-tree from
// pipeline/kdtree's buildKdTree, packed); `out` is allocated for
// queryCount × maxK. Return the kernel's device seconds. The hash-grid search needs every
// query's radius ≤ cellSize / 2 (the caller checks; knnHashGridOnDevice does).
double knnSearchKdTree(Device& device, const KnnKdTree& tree, const cl::Buffer& queries, size_t queryCount,
                       uint32_t maxK, DeviceKnnOutput& out);
double knnSearchHashGrid(Device& device, const DeviceHashGrid& grid, const cl::Buffer& queries, size_t queryCount,
                         uint32_t maxK, DeviceKnnOutput& out);

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
KnnResult knnHashGridOnDevice(Device& device, const std::vector<PclPhoton>& map, const std::vector<PclKnnQuery>& queries);

// The whole thing from a photon map in deposit order: builds the structure on the device
// (buildKdTree, or buildHashGrid for r_max = the largest query radius) and searches. Indices
// refer to `map`.
KnnResult knnOnDevice(Device& device, const std::vector<PclPhoton>& map, KnnStructure structure,
                      const std::vector<PclKnnQuery>& queries);

// Largest k over the queries; InputError when a k is 0 or above PCL_KNN_MAX_K or a radius is
// negative or NaN.
uint32_t knnMaxK(const std::vector<PclKnnQuery>& queries);

}  // namespace pcl
