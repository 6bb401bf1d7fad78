// Precomputed irradiance on the device (Christensen 1999, "Faster Photon Map Global
// Illumination"; kernels/precomputed_irradiance.cl; kernels/README.md, "precomputed
// irradiance"): the irradiance is estimated once at every m-th photon of the global map (in
// deposit order) with that photon's own normal, through the full estimate (pipeline/estimate),
// and stored with the photon's position and normal in a left-balanced kd-tree; a later lookup
// is one nearest-neighbour search with the normal test inside it, instead of a k-nearest-
// neighbour estimate. Built once per photon pass, looked up by any number of query batches.
//
// Unlike Christensen, the estimates search the OTHER photons (those not selected, a map of
// (m − 1)/m of the records, their result scaled by m/(m − 1)): an estimate that counts the
// stored points' photons correlates with how the stored points crowd, and the nearest-point
// lookup, which picks points with large Voronoi cells more often, then reads low (−3 % at m = 4,
// k = 50 on a uniform plane; +2 % when the photon itself is counted). Leaving them out makes the
// two independent (a thinned Poisson process), and the mean lookup matches the full estimate's.
// Each point also keeps a cover, (f r)² with r its estimate's radius and f = 2: a lookup takes the
// nearest point whose cover holds the query, so a bright point does not answer for a dark region
// its photons never reached (gltf-room: 92 of 10 000 surface points whose full estimate is 0 read
// a neighbour's light without it, and the mean lookup moves from 0.9 % to 0.1 % of the full
// estimate's). f = 1 leaves holes (a query farther than r from every stored point: black specks,
// ~0.3 % of the cornell-box points); f = 2 has the holes of no cover at all.
// The CPU twin is host/reference/precomputed_irradiance.h.
//
//   PrecomputedIrradianceOptions o;  o.maxRadius = rMax;              // every 4th photon, k = 50
//   DeviceIrradianceMap irr = precomputeIrradiance(device, globalPhotons, n, o, nullptr);
//   DeviceIrradianceLookup out;
//   lookupIrradiance(device, irr, queryBuffer, queryCount, out);      // PclEstimateQuery, k unused
//   // out.irradiance: float4 (r, g, b, d²) per query; out.chosen: the photon index or PCL_NO_HIT
//
// Host vectors in and out, for the checks and the tests: lookupIrradianceOnDevice in
// check/on_device.h.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "pipeline/device_scene.h"
#include "pipeline/estimate.h"
#include "prep/irradiance_settings.h"
#include "shared/types.h"

namespace pcl {

struct IrradianceTiming {
    double selectSeconds = 0.0;  // device: selection, the estimate queries, the others' map
    double mapSeconds = 0.0;     // wall: the others' search structure (PhotonMapOnDevice)
    EstimateTiming estimate;     // device: the estimates at the stored points
    double treeSeconds = 0.0;    // wall: the lookup kd-tree (build and pack)
};

// The stored points on the device.
struct DeviceIrradianceMap {
    cl::Buffer points;         // PclIrradiancePoint[count] in selection order: point j is photon j·m
    cl::Buffer cover;          // float[count], selection order: (f r)², r² each point's estimate's
    cl::Buffer nondirect;      // float4[count], selection order: the irradiance of the photons of
                               // bounce > 0 alone (what a PCL_QUERY_NONDIRECT lookup answers)
    cl::Buffer nodes;          // the same points in left-balanced heap order (node h's children
                               // 2h+1, 2h+2), split axis in bits 30..31 of `photon`
    cl::Buffer nodeCover;      // float[count], heap order
    cl::Buffer nodeNondirect;  // float4[count], heap order
    cl::Buffer buckets;        // the last three levels by subtree, 9 rows per bucket (the lookup's
                               // float8 tests; kernels/precomputed_irradiance.cl)
    uint32_t bucketFirst = 0;  // the first heap node stored in a bucket (knnBucketFirst)
    size_t count = 0;
    float minNormalCos = 0.9f;  // the lookup's normal threshold
    IrradianceTiming timing;
};

// (a) select, (b) estimate, (c) store and build: the whole precomputation from the global map's
// `count` records in `photons` (deposit order; left untouched). `scene` is needed when
// options.estimate.visibility is on. The others' map is built with options.estimate.structure
// (the hash grid's origin from `lo`, the map's bounds minimum; the kd-tree needs none).
DeviceIrradianceMap precomputeIrradiance(Device& device, const cl::Buffer& photons, size_t count,
                                         const PrecomputedIrradianceOptions& options, const DeviceScene* scene,
                                         const float* lo = nullptr);
// Upload and precompute.
DeviceIrradianceMap precomputeIrradiance(Device& device, const std::vector<PclPhoton>& map,
                                         const PrecomputedIrradianceOptions& options, const DeviceScene* scene);

// One device buffer of the stage as the memory plan (pipeline/memory_plan.h) lists buffers: the
// label it is allocated under, its elements and their size (it asks max(count, 1) × elementBytes).
struct IrradianceBufferSize {
    std::string what;
    size_t count = 0;
    size_t elementBytes = 0;
};
// The buffers precomputeIrradiance allocates itself for a global map of `records` photons with
// step `every` (points, estimate queries, covers, the others' copy, estimates, the tree's input,
// nodes and covers) and, for lookupQueries > 0, one lookup batch's outputs. Not listed (the
// plan's own formulas give them): the others' search structure (PhotonMapOnDevice over
// records − ⌈records/every⌉ photons), estimateBuffers' kNN batch buffers (k) and the kd-tree
// build's workspace over ⌈records/every⌉ points.
std::vector<IrradianceBufferSize> precomputedIrradianceBuffers(size_t records, uint32_t every,
                                                               size_t lookupQueries = 0);

// (c) alone: the lookup tree over `count` points, their covers (squared radii) and nondirect
// irradiance (float4) already on the device (irradiance filled in, `photon` below 2^30 and
// distinct: it breaks ties). The map keeps the three buffers.
DeviceIrradianceMap buildIrradianceTree(Device& device, const cl::Buffer& points, const cl::Buffer& cover,
                                        const cl::Buffer& nondirect, size_t count, float minNormalCos);
// Upload and build; an empty `cover` lets every point answer any query within its radius (∞);
// an empty `nondirect` makes it each point's irradiance (no direct part told apart).
DeviceIrradianceMap uploadIrradiancePoints(Device& device, const std::vector<PclIrradiancePoint>& points,
                                           float minNormalCos, const std::vector<float>& cover = {},
                                           const std::vector<cl_float4>& nondirect = {});

// The points in selection order, and the tree nodes in heap order, downloaded.
std::vector<PclIrradiancePoint> downloadIrradiancePoints(Device& device, const DeviceIrradianceMap& map);
std::vector<float> downloadIrradianceCover(Device& device, const DeviceIrradianceMap& map);  // selection order
// The nondirect irradiance, selection order, 4 floats per point (r, g, b, 0: the twin's layout).
std::vector<float> downloadIrradianceNondirect(Device& device, const DeviceIrradianceMap& map);

// (d) lookups on the device.
struct DeviceIrradianceLookup {
    cl::Buffer irradiance;  // float4 per query: r, g, b (W/m²), d² to the chosen point; 0s if none
    cl::Buffer chosen;      // uint per query: the chosen point's photon index, PCL_NO_HIT if none
    size_t queries = 0;
};

// For each of `queryCount` PclEstimateQuery (x, y, z, maxRadius2, unit normal; of k only the
// PCL_QUERY_NONDIRECT bit, which answers with the point's nondirect irradiance) the
// nearest stored point within maxRadius2 (usually the estimate's r_max²) whose cover holds the
// query and whose normal agrees. Allocates `out` (reused when it
// already holds queryCount); returns the kernel's device seconds. zeroRadiusIsNone: a query
// with maxRadius2 = 0 is answered "none" (0, PCL_NO_HIT) without a search, as IrradianceSource
// asks (the final gather's rays without a diffuse hit); otherwise it finds a point at d² = 0.
double lookupIrradiance(Device& device, const DeviceIrradianceMap& map, const cl::Buffer& queries, size_t queryCount,
                        DeviceIrradianceLookup& out, bool zeroRadiusIsNone = false);

}  // namespace pcl
