// `photoncl check SCENE --stage estimate`: the device irradiance estimate (pipeline/estimate,
// kernels/estimate.cl) against its CPU twin (reference/estimate: brute-force kNN, host BVH) on
// the scene's own photon maps.
//
// The maps come from the device photon pass (runPhotonPass, with projection maps). Queries:
// real surface points — the closest hits of camera rays through random pixels, with the
// geometric normal turned toward the camera — and uniform random points in the map's bounding
// box with random unit normals. r_max = radiusFraction × the scene's bounding-box diagonal
// (each query its own maxRadius2, uniform in [¼, 1] × r_max²). For each map × query set ×
// structure × filter × visibility (off, and on for surface queries): the same photons found
// and used per query, irradiance within 1e-5 relative (exp, division and sqrt may differ by an ulp
// between the device and the host library), r² equal, no NaN. Any divergence fails.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "pipeline/estimate.h"
#include "prep/prepared_scene.h"
#include "prep/scene_buffers.h"
#include "scene/scene.h"

namespace pcl {

struct EstimateCheckOptions {
    uint32_t photons = 50000;  // paths per photon pass (global and caustic each)
    uint32_t surfaceQueries = 4000;
    uint32_t randomQueries = 2000;
    uint32_t k = 50;
    float radiusFraction = 0.05f;  // r_max / scene bounding-box diagonal
    float coneK = 1.1f;
    std::vector<EstimateFilter> filters = allEstimateFilters();
    std::vector<KnnStructure> structures = {KnnStructure::KdTree, KnnStructure::HashGrid};
    bool visibility = true;  // also check the visibility test on the surface queries
    uint64_t seed = 1;
};

struct EstimateCheckRow {
    std::string map;        // "global" / "caustic"
    std::string queries;    // "random" / "surface"
    std::string structure;  // "kd-tree" / "hash grid"
    std::string filter;     // "box", ...
    bool visibility = false;
    size_t photons = 0, queryCount = 0;
    size_t nonzero = 0;           // queries the twin estimates nonzero
    size_t used = 0;              // photons used by the twin, summed over queries
    size_t countMismatches = 0;   // queries whose found or used counts differ
    size_t radiusMismatches = 0;  // queries whose r² differs
    size_t nans = 0;              // non-finite values from either side
    double maxRelError = 0.0;     // irradiance, per channel: |d − t| / max(|d|, |t|)
    double nondirectError = 0.0;  // nondirect part decoded: max channel |d − t| / the larger max channel
    double deviceSeconds = 0.0;   // kNN + estimate kernels
    bool passed() const;
};

struct EstimateCheckReport {
    std::vector<EstimateCheckRow> rows;
    double photonSeconds = 0.0, twinSeconds = 0.0, deviceSeconds = 0.0;
    bool passed() const;        // every row passed (and there is at least one)
    std::string table() const;  // one line per row, then the tolerances
};

// Relative tolerance on irradiance between the device and the twin.
constexpr double kEstimateTolerance = 1e-5;
// The nondirect part (PclEstimate::nondirect, RGBE: 8 mantissa bits under a shared exponent):
// sums an ulp apart may round to neighbouring mantissas, one step of the largest channel's 2^e.
constexpr double kNondirectTolerance = 1.0 / 128.0;

EstimateCheckReport checkEstimate(Device& device, const Scene& scene, const EstimateCheckOptions& options = {});
// The same on built geometry and buffers (projection maps included if a caustic map is wanted).
EstimateCheckReport checkEstimate(Device& device, const Scene& scene, const SceneGeometry& geometry,
                                  const SceneBuffers& buffers, const EstimateCheckOptions& options = {});

// `count` estimate queries at the closest hits of camera rays through random pixels (misses
// skipped, at most 8 × count rays), normal = the geometric normal on the camera's side;
// maxRadius2 uniform in [¼, 1] × maxRadius².
std::vector<PclEstimateQuery> surfaceEstimateQueries(const Scene& scene, const SceneGeometry& geometry, uint32_t count,
                                                     float maxRadius, uint32_t k, uint64_t seed);

// Adds the comparison of device estimates with the twin's into row.
void compareEstimates(const std::vector<PclEstimate>& twin, const std::vector<PclEstimate>& device,
                      EstimateCheckRow& row);

}  // namespace pcl
