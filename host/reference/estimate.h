// CPU twin of the irradiance estimate (kernels/README.md, "estimate"), written from the spec:
// brute-force kNN (reference/knn.h), then per query
//   E = Σ_p w(d_p/r) ΔΦ_p / (norm · π r²)
// over the neighbours in (d², index) order that pass the rejection tests (incoming side, normal
// agreement, and with settings.visibility an unoccluded lifted segment, traced with the host BVH
// SceneGeometry::intersect). Zero photons give exactly 0.
#pragma once
#include <cstdint>
#include <vector>

#include "geometry/scene_geometry.h"
#include "prep/estimate_settings.h"
#include "reference/knn.h"
#include "shared/types.h"

namespace pcl {

// The filter weight at u² = d²/r² in float, as the kernel computes it (u = √u² where needed).
float referenceFilterWeight(const PclEstimateParams& p, float u2);

// The estimate at one query from its neighbours (count of them, in ascending (d², index) order,
// radius2 = the last one's d²). For callers with their own search (precomputed irradiance).
// geometry is required when settings.visibility is on.
PclEstimate referenceEstimateFromNeighbours(const std::vector<PclPhoton>& map, const PclEstimateQuery& query,
                                            const uint32_t* indices, const float* dist2, uint32_t count, float radius2,
                                            const EstimateSettings& settings, const SceneGeometry* geometry);

// Every query from a brute-force result already computed for these queries (knn.stride may
// exceed a query's k: its first k slots are the answer for k).
std::vector<PclEstimate> referenceEstimateWithKnn(const std::vector<PclPhoton>& map,
                                                  const std::vector<PclEstimateQuery>& queries, const ReferenceKnn& knn,
                                                  const EstimateSettings& settings, const SceneGeometry* geometry,
                                                  unsigned threads = 0);

// Brute-force kNN and the estimate. threads: 0 = all cores.
std::vector<PclEstimate> referenceEstimate(const std::vector<PclPhoton>& map,
                                           const std::vector<PclEstimateQuery>& queries,
                                           const EstimateSettings& settings, const SceneGeometry* geometry,
                                           unsigned threads = 0);

// The kNN queries of estimate queries (position, maxRadius2, k).
std::vector<PclKnnQuery> estimateKnnQueries(const std::vector<PclEstimateQuery>& queries);

}  // namespace pcl
