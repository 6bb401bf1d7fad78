// `photoncl check SCENE --stage knn`: the device k-nearest-neighbour search (pipeline/knn,
// kernels/knn.cl) through both structures against the brute force (reference/knn) on the
// scene's own photon maps.
//
// The maps come from the device photon pass (runPhotonPass, with projection maps). Queries:
// uniform random points in the map's bounding box (grown by r_max), and real surface points —
// the closest hits of camera rays through random pixels. r_max = radiusFraction × the scene's
// bounding-box diagonal (every query its own maxRadius2, uniform in [¼, 1] × r_max²). For each
// map × query set × structure × k: the same neighbour count, the same photon indices in the
// same order, squared distances within 1e-6 relative, r² ≤ maxRadius2 and r² = the last
// neighbour's d² (0 when none). Any mismatch fails.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "check/on_device.h"
#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "pipeline/knn.h"
#include "prep/prepared_scene.h"
#include "prep/scene_buffers.h"
#include "reference/knn.h"
#include "scene/scene.h"

namespace pcl {

struct KnnCheckOptions {
    uint32_t photons = 50000;  // paths per photon pass (global and caustic each)
    uint32_t randomQueries = 10000;
    uint32_t surfaceQueries = 10000;
    std::vector<uint32_t> ks = {1, 50, 500};
    float radiusFraction = 0.05f;  // r_max / scene bounding-box diagonal
    uint64_t seed = 1;
};

struct KnnCheckRow {
    std::string map;        // "global" / "caustic"
    std::string queries;    // "random" / "surface"
    std::string structure;  // "kd-tree" / "hash grid"
    uint32_t k = 0;
    size_t photons = 0, queryCount = 0;
    size_t neighbours = 0;        // returned by the brute force, summed over queries
    size_t empty = 0;             // queries the brute force finds nothing for
    size_t countMismatches = 0;   // queries whose counts differ
    size_t indexMismatches = 0;   // neighbour slots whose photon index differs
    size_t radiusViolations = 0;  // r² > maxRadius2, or r² ≠ last d² (0 if none)
    double maxDist2Error = 0.0;   // relative, over slots with equal indices
    double deviceSeconds = 0.0;   // search kernel
    bool passed() const;
};

struct KnnCheckReport {
    std::vector<KnnCheckRow> rows;
    double bruteSeconds = 0.0, deviceSeconds = 0.0, photonSeconds = 0.0;
    bool passed() const;        // every row passed (and there is at least one)
    std::string table() const;  // one line per row, then the tolerances
};

KnnCheckReport checkKnn(Device& device, const Scene& scene, const KnnCheckOptions& options = {});
// The same on built geometry and buffers (projection maps included if a caustic map is wanted).
KnnCheckReport checkKnn(Device& device, const Scene& scene, const SceneGeometry& geometry, const SceneBuffers& buffers,
                        const KnnCheckOptions& options = {});

// Query points: `count` closest hits of camera rays through random pixels (misses skipped, at
// most 8 × count rays), and `count` uniform points in [lo, hi]³.
std::vector<PclKnnQuery> surfaceKnnQueries(const Scene& scene, const SceneGeometry& geometry, uint32_t count,
                                           float maxRadius, uint32_t k, uint64_t seed);
std::vector<PclKnnQuery> randomKnnQueries(const float lo[3], const float hi[3], uint32_t count, float maxRadius,
                                          uint32_t k, uint64_t seed);

// Adds the comparison of a device result with the brute force (whose stride may exceed k: its
// first k slots per query are the answer for k, as the order is total) into row.
void compareKnn(const std::vector<PclKnnQuery>& queries, const ReferenceKnn& brute, const KnnResult& device,
                KnnCheckRow& row);

}  // namespace pcl
