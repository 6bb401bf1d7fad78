// CPU twin of precomputed irradiance (kernels/README.md, "precomputed irradiance"; Christensen
// 1999), written from the spec: the points are every m-th photon of the global map in deposit
// order (photon j·m for j < ⌈n/m⌉) with that photon's position and normal word; each point's
// irradiance is m/(m − 1) times the estimate twin's (reference/estimate) at the photon's
// position with its decoded normal, in the map of the photons NOT selected, and its cover is
// f² (coverFactor², in float) times that estimate's r² (∞ for f = ∞); a lookup is the brute-force nearest point with d² ≤ maxRadius2, d² ≤ its cover
// and an agreeing normal (n_p·n_q ≥ minNormalCos), ties in d² going to the lower photon index.
#pragma once
#include <cstdint>
#include <vector>

#include "geometry/scene_geometry.h"
#include "prep/irradiance_settings.h"
#include "shared/types.h"

namespace pcl {

// Every `every`-th photon of `map` (every ≥ 2), irradiance 0, `photon` = its map index.
std::vector<PclIrradiancePoint> referenceSelectIrradiancePoints(const std::vector<PclPhoton>& map, uint32_t every);

// The estimate query at a selected point: its position, its decoded normal, maxRadius2 and k.
PclEstimateQuery referenceIrradianceEstimateQuery(const PclIrradiancePoint& point, float maxRadius2, uint32_t k);

// The octahedral normal word decoded as the README states: c = q/32767, z = 1 − |u| − |v|,
// unfolded when z < 0, then each component divided by the length.
void referenceDecodeNormal(uint32_t word, float n[3]);

// Fills r, g, b of each point (any subset of a selection) with m/(m − 1) (in float) times the
// estimate twin's irradiance (referenceEstimate: brute-force kNN) at its query in the map of the
// photons whose index is not a multiple of m, each cover (when `cover` is given) with f²
// times that estimate's r², and (when `nondirect` is given, 4 floats per point: r, g, b, 0) the
// estimate's nondirect RGBE decoded times m/(m − 1). geometry: needed with visibility.
void referenceEstimateIrradiancePoints(const std::vector<PclPhoton>& map, std::vector<PclIrradiancePoint>& points,
                                       const PrecomputedIrradianceOptions& options, const SceneGeometry* geometry,
                                       unsigned threads = 0, std::vector<float>* cover = nullptr,
                                       std::vector<float>* nondirect = nullptr);

// Selection and estimates: the twin of precomputeIrradiance's points and covers (selection order).
std::vector<PclIrradiancePoint> referencePrecomputeIrradiance(const std::vector<PclPhoton>& map,
                                                              const PrecomputedIrradianceOptions& options,
                                                              const SceneGeometry* geometry, unsigned threads = 0,
                                                              std::vector<float>* cover = nullptr,
                                                              std::vector<float>* nondirect = nullptr);

struct ReferenceIrradianceLookup {
    std::vector<float> irradiance;  // queries × 4: r, g, b, d² of the chosen point; 0s when none
    std::vector<uint32_t> chosen;   // per query: the chosen point's photon index, PCL_NO_HIT when none
};

// Brute force over `points` (any order; `photon` below 2^30) with their covers (empty: no limit).
// Query normals are used as given. A query with PCL_QUERY_NONDIRECT in k gets the chosen point's
// `nondirect` (4 floats per point; empty: its irradiance).
ReferenceIrradianceLookup referenceLookupIrradiance(const std::vector<PclIrradiancePoint>& points,
                                                    const std::vector<float>& cover,
                                                    const std::vector<PclEstimateQuery>& queries, float minNormalCos,
                                                    unsigned threads = 0, const std::vector<float>& nondirect = {});

}  // namespace pcl
