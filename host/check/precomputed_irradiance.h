// The precomputed-irradiance check (pipeline/precomputed_irradiance against its twin and
// against the full estimate; for `photoncl check SCENE --stage estimate`):
//   selection    the device's stored points are the twin's (every m-th photon), byte for byte
//                but for the irradiance;
//   stored       the irradiance stored at `twinPoints` of them (spread over the map) equals the
//                twin's (reference/estimate in the map of the other photons, × m/(m − 1))
//                within kIrradianceStoredTolerance relative, and its cover (f² × the estimate's
//                r²) bit for bit (both searches return the brute force's neighbours);
//   lookup       on the device's own points and covers, device lookups choose the twin's nearest
//                point (brute force with the cover and normal tests) for every random and surface query and
//                return its stored value and d² exactly;
//   exact        a lookup at each stored point's position with its own decoded normal returns
//                that point (or a coincident one of lower photon index) at d² = 0 and its value;
//   accuracy     (reported, not part of passed(): it depends on the photon count) over the
//                surface queries, the mean of the lookups is within 1 % of the mean
//                of the full estimate at the same points (the per-point RMS relative
//                difference is reported, not asserted: one stored point stands for ~m photons);
//   speed        the full estimate's device time (kNN + estimate) over the lookup's, per query
//                (a figure, never a pass/fail criterion).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "pipeline/precomputed_irradiance.h"
#include "prep/prepared_scene.h"
#include "prep/scene_buffers.h"
#include "scene/scene.h"

namespace pcl {

struct IrradianceCheckOptions {
    uint32_t photons = 50000;         // global paths of the photon pass (scene check)
    uint32_t every = 4;               // m
    uint32_t k = 50;                  // photons per estimate, full and stored
    float coverFactor = 2.0f;         // PrecomputedIrradianceOptions::coverFactor
    float radiusFraction = 0.05f;     // r_max / scene bounding-box diagonal (scene check)
    uint32_t surfaceQueries = 10000;  // camera-ray hits (scene check)
    uint32_t randomQueries = 10000;   // points in the map's box, normals of random photons
    uint32_t twinPoints = 2000;       // stored points the estimate twin recomputes
    uint32_t twinQueries = 4000;      // per query set: lookups the brute force repeats
    EstimateSettings estimate;        // the filter and normal test of both estimates
    uint64_t seed = 1;
};

struct IrradianceCheckReport {
    std::string name;                // the scene or map
    size_t photons = 0, points = 0;  // global map records, stored points
    float maxRadius = 0.0f;
    // selection
    size_t selectionMismatches = 0;  // points differing from the twin's in position, normal or photon
    // stored irradiance vs the estimate twin
    size_t storedCompared = 0;
    double storedMaxError = 0.0;     // max |device − twin| / max(|twin|, 1e-3 × mean stored), per channel
    size_t coverMismatches = 0;      // covers not bit-equal to the twin's
    double nondirectMaxError = 0.0;  // stored nondirect irradiance: max |device − twin| over the larger of
                                     // the twin's largest channel and 1e-3 × mean stored (RGBE-rounded)
    // lookup vs brute force (random, surface)
    size_t lookupCompared = 0, choiceMismatches = 0, valueMismatches = 0, lookupEmpty = 0;
    // exact points
    size_t exactCompared = 0, exactFailures = 0;
    // accuracy: scalar irradiance (r + g + b) / 3 at the surface queries
    size_t accuracyQueries = 0;
    double meanEstimate = 0.0, meanLookup = 0.0;
    double meanRelativeError() const;    // |meanLookup / meanEstimate − 1|
    double rmsRelativeDifference = 0.0;  // over queries with a non-zero estimate: √mean(((L − E)/E)²)
    double rmsDifferenceOverMean = 0.0;  // √mean((L − E)²) / mean E, over every query
    size_t estimateZeroLookupNot = 0, lookupZeroEstimateNot = 0;
    // speed (device seconds over the surface queries)
    double estimateSeconds = 0.0, lookupSeconds = 0.0;
    double speedUp() const;          // estimateSeconds / lookupSeconds (0 if no lookup time)
    double precomputeSeconds = 0.0;  // device: selection + estimates at the points; wall: tree
    double photonSeconds = 0.0, twinSeconds = 0.0;

    bool passed() const;        // every kernel-vs-twin criterion (accuracy is not one)
    bool accurate() const;      // the lookup mean within kIrradianceMeanTolerance of the full estimate's
    std::string table() const;  // one line per part, the tolerances, then passed/FAILED
};

constexpr double kIrradianceStoredTolerance = 1e-5;  // relative, device vs twin: the estimate's own
constexpr double kIrradianceMeanTolerance = 0.01;    // lookup mean vs full-estimate mean

// The scene's global map from a device photon pass, then the check on it.
IrradianceCheckReport checkPrecomputedIrradiance(Device& device, const Scene& scene,
                                                 const IrradianceCheckOptions& options = {});
IrradianceCheckReport checkPrecomputedIrradiance(Device& device, const Scene& scene, const SceneGeometry& geometry,
                                                 const SceneBuffers& buffers,
                                                 const IrradianceCheckOptions& options = {});

// The check on any global map with given surface queries (position, unit normal facing the side
// looked at, maxRadius2 = r_max², k) and r_max. Random queries are drawn here. With
// options.estimate.visibility both scene arguments are required.
IrradianceCheckReport checkPrecomputedIrradianceOnMap(Device& device, const std::vector<PclPhoton>& map,
                                                      const std::vector<PclEstimateQuery>& surface, float maxRadius,
                                                      const IrradianceCheckOptions& options, const std::string& name,
                                                      const DeviceScene* deviceScene = nullptr,
                                                      const SceneGeometry* geometry = nullptr);

}  // namespace pcl
