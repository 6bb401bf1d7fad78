// CPU twin of the estimates at the eye hits (kernels/README.md, "Eye pass: estimates at the eye
// hits"): caustics and direct visualisation, L = throughput × ρd × E / π.
#pragma once
#include <vector>

#include "reference/final_gather.h"
#include "shared/types.h"

namespace pcl {

std::vector<PclEstimateQuery> referenceEyeEstimateQueries(const std::vector<PclEyeHit>& hits,
                                                          const PclEyeEstimateParams& params);
std::vector<PclRadiance> referenceEyeEstimateResolve(const std::vector<PclEyeHit>& hits,
                                                     const std::vector<Vec3>& irradiance);
// Both, with the irradiance from `irradiance`.
std::vector<PclRadiance> referenceEstimateAtEyeHits(const std::vector<PclEyeHit>& hits,
                                                    const PclEyeEstimateParams& params,
                                                    const ReferenceIrradiance& irradiance);

}  // namespace pcl
