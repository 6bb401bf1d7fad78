// k nearest photons on the device (kernels/knn.cl; kernels/README.md, "Photon maps", knn): per
// query the k photons nearest a point within its maximum radius, through the left-balanced
// kd-tree or the hash grid, a bounded max-heap per query with ties in distance broken by the
// lower photon index. Both structures return exactly what the brute force
// (host/reference/knn.cpp) returns: the same indices in the same order and the same squared
// distances.
//
//   KnnKdTree tree = packKdTree(device, buildKdTree(device, photons, n));  // built once
//   DeviceKnnOutput out;               // queries: PclKnnQuery x, y, z, maxRadius2, k (1..500)
//   knnSearchKdTree(device, tree, queries, queryCount, maxK, out);
//   // per query q: out.counts[q] neighbours, out.indices / out.dist2 [q * out.stride + j]
//
// Host vectors in and out, for the checks and the tests: knnOnDevice and the others in
// check/on_device.h.
#pragma once
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "pipeline/hashgrid.h"
#include "pipeline/kdtree.h"
#include "prep/knn_structure.h"
#include "shared/types.h"

namespace pcl {

// The search kernels' outputs on the device.
struct DeviceKnnOutput {
    cl::Buffer counts, indices, dist2, radius2;
    uint32_t stride = 0;
    size_t queries = 0;
};

// A kd-tree ready for the search (knn_pack_kdtree): buildKdTree's upper nodes packed as float4
// (x, y, z, photon index | split axis << 30 as the bits of w), one load per visited node, then
// the last three levels as buckets of ≤ 7 nodes that the search tests with float8 arithmetic
// (kernels/shared/kd_buckets.h).
struct KnnKdTree {
    cl::Buffer nodes;
    size_t count = 0;
    uint32_t bucketFirst = 0;  // the first bucket root: 2^D − 1, D = max(levels − 3, 0)
};
// The first heap node stored in a bucket, and the float4 elements of the packed tree (the
// memory plan's size): one per node, and PCL_KD_BUCKET_PAD_FLOATS of padding.
uint32_t knnBucketFirst(size_t count);
size_t knnPackedKdTreeElements(size_t count);
// InputError for trees of 2^30 photons or more (the index field).
KnnKdTree packKdTree(Device& device, const DeviceKdTree& tree);

// Heap capacity the kernel is specialised for (-DPCL_KNN_CAP): the smallest of 8, 32, 64, 128,
// 256, 500 holding maxK. InternalError outside 1..PCL_KNN_MAX_K.
uint32_t knnHeapCapacity(uint32_t maxK);

// Queries per search launch for the memory plan (and the host-vector searches of
// check/on_device.h): as many as keep every buffer of the batch (queries 32 B, indices and dist2
// 4·maxK B each per query) under maxAlloc and the batch's buffers together under a quarter of
// globalMem; whole work-groups of 64. A smaller maxAlloc (--max-buffer-mib) only splits the
// work: the results are the same.
size_t knnQueryBatch(size_t maxAlloc, size_t globalMem, uint32_t maxK);

// The searches on structures and queries already on the device (the kd-tree from
// pipeline/kdtree's buildKdTree, packed); `out` is allocated for
// queryCount × maxK. Return the kernel's device seconds. The hash-grid search needs every
// query's radius ≤ cellSize / 2 (the caller checks).
// firstRadius2 (kd-tree): a first search bound, a guess of the k-th photon's d²; queries that
// find fewer than k within it search again with their maxRadius2. Only the speed depends on it.
double knnSearchKdTree(Device& device, const KnnKdTree& tree, const cl::Buffer& queries, size_t queryCount,
                       uint32_t maxK, DeviceKnnOutput& out, float firstRadius2 = INFINITY);
double knnSearchHashGrid(Device& device, const DeviceHashGrid& grid, const cl::Buffer& queries, size_t queryCount,
                         uint32_t maxK, DeviceKnnOutput& out);

// Largest k over the queries; InternalError when a k is 0 or above PCL_KNN_MAX_K or a radius is
// negative or NaN.
uint32_t knnMaxK(const std::vector<PclKnnQuery>& queries);

}  // namespace pcl
