// CPU twin of final gathering (kernels/README.md, "Eye pass: final gather") and of the
// estimates at the eye hits. The irradiance at the gather hits comes from a host function of
// the queries (the twin estimate reference/estimate.h, a precomputed-irradiance twin, or an
// analytic one in a test).
#pragma once
#include <functional>
#include <vector>

#include "geometry/scene_geometry.h"
#include "prep/area_light_table.h"
#include "prep/estimate_settings.h"
#include "prep/scene_buffers.h"
#include "shared/types.h"

namespace pcl {

// E rgb at each query (a query with maxRadius2 = 0 gives 0).
using ReferenceIrradiance = std::function<std::vector<Vec3>(const std::vector<PclEstimateQuery>&)>;

// The brute-force lookup of precomputed irradiance points (their covers and nondirect parts,
// reference/precomputed_irradiance.h) as a ReferenceIrradiance.
ReferenceIrradiance referencePrecomputedIrradiance(const std::vector<PclIrradiancePoint>& points,
                                                   const std::vector<float>& cover, float minNormalCos,
                                                   const std::vector<float>& nondirect);

// The twin estimate (brute-force kNN) on `map` as a ReferenceIrradiance.
ReferenceIrradiance referenceEstimateIrradiance(const std::vector<PclPhoton>& map, const EstimateSettings& settings,
                                                const SceneGeometry* geometry);

// The importance histograms (params.histogramCells = G > 0): per record the cumulative table
// of G² cells from the params.k photons of `map` nearest the hit within params.maxRadius2
// (brute-force kNN), records × G² floats.
std::vector<float> referenceGatherHistograms(const std::vector<PclPhoton>& map, const std::vector<PclEyeHit>& hits,
                                             const PclGatherParams& params);

// Gather ray j = i·N + g: the query and what it gathered. cdf: record i's histogram table
// (G² floats) when params.histogramCells > 0; table: the triangle lights' choice (the close hits'
// direct light, params.closeDistance > 0).
void referenceGatherRay(const SceneGeometry& geometry, const SceneBuffers& buffers, const AreaLightTable& table,
                        const PclGatherParams& params, const PclEyeHit& h, uint32_t g, PclEstimateQuery& query,
                        PclGatherHit& gathered, const float* cdf = nullptr);

struct ReferenceGather {
    std::vector<PclEstimateQuery> queries;
    std::vector<PclGatherHit> gathered;
    std::vector<Vec3> irradiance;
    std::vector<PclRadiance> radiance;
};
// histograms: records × G² tables when params.histogramCells > 0.
ReferenceGather referenceFinalGather(const SceneGeometry& geometry, const SceneBuffers& buffers,
                                     const std::vector<PclEyeHit>& hits, const PclGatherParams& params,
                                     const ReferenceIrradiance& irradiance,
                                     const std::vector<float>* histograms = nullptr);
// The resolve alone (radiance from records, gathered rays and irradiance).
std::vector<PclRadiance> referenceResolveGather(const PclGatherParams& params, const std::vector<PclEyeHit>& hits,
                                                const std::vector<PclGatherHit>& gathered,
                                                const std::vector<Vec3>& irradiance);

}  // namespace pcl
