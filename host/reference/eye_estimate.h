// CPU twin of the estimates at the eye hits (kernels/README.md, "Eye pass: estimates at the eye
// hits"): caustics and direct visualisation, L = throughput × ρd × E / π.
#pragma once
#include <vector>

#include "reference/final_gather.h"
#include "shared/types.h"

namespace pcl {

// primInfo (the scene's) is read only with params.atShutterOpen (the global map).
std::vector<PclEstimateQuery> referenceEyeEstimateQueries(const std::vector<PclEyeHit>& hits,
                                                          const PclEyeEstimateParams& params,
                                                          const std::vector<PclPrimInfo>& primInfo);
std::vector<PclRadiance> referenceEyeEstimateResolve(const std::vector<PclEyeHit>& hits,
                                                     const std::vector<Vec3>& irradiance);
// Both, with the irradiance from `irradiance`.
std::vector<PclRadiance> referenceEstimateAtEyeHits(const std::vector<PclEyeHit>& hits,
                                                    const PclEyeEstimateParams& params,
                                                    const std::vector<PclPrimInfo>& primInfo,
                                                    const ReferenceIrradiance& irradiance);

}  // namespace pcl
