// Eye pass stage 5: photon-map estimates at the diffuse eye hits (kernels/eye_estimate.cl;
// kernels/README.md, "Eye pass: estimates at the eye hits"):
//  * caustics: the caustic map read directly at the first diffuse hit (LS+DE);
//  * direct visualisation (preview): the global map read at the first diffuse hit, instead of
//    final gathering (its estimate then includes direct light, so the preview adds only
//    emitted radiance and — optionally — nothing else).
// Both are L = throughput × ρd/π × E(hit, n), E from an IrradianceSource. The twin is
// host/reference/eye_estimate.h.
#pragma once
#include <cstdint>
#include <vector>

#include "device/device.h"
#include "pipeline/irradiance_source.h"
#include "shared/types.h"

namespace pcl {

// Enqueues eye_estimate_queries: hits in, queries (PclEstimateQuery[sampleCount]) out; records
// without a diffuse hit get maxRadius2 = 0. primInfo (the scene's PclPrimInfo) is read only with
// params.atShutterOpen (the global map: kernels/shared/shutter_open.h).
cl::Event eyeEstimateQueries(Device& device, const PclEyeEstimateParams& params, const cl::Buffer& hits,
                             const cl::Buffer& primInfo, cl::Buffer& queries);
// Enqueues eye_estimate_resolve: radiance = throughput × ρd/π × E.
cl::Event eyeEstimateResolve(Device& device, const PclEyeEstimateParams& params, const cl::Buffer& hits,
                             const cl::Buffer& irradiance, cl::Buffer& radiance);

// Queries, source, resolve on buffers (params.irradianceStride taken from the source); returns
// device seconds. Used for both the caustic map and direct visualisation.
double estimateAtEyeHits(Device& device, PclEyeEstimateParams params, const cl::Buffer& hits,
                         const cl::Buffer& primInfo, IrradianceSource& source, cl::Buffer& radiance);
inline double causticRadiance(Device& device, const PclEyeEstimateParams& params, const cl::Buffer& hits,
                              const cl::Buffer& primInfo, IrradianceSource& causticMap, cl::Buffer& radiance) {
    return estimateAtEyeHits(device, params, hits, primInfo, causticMap, radiance);
}

// InternalError when params.k is outside 1..PCL_KNN_MAX_K or maxRadius2 is negative or NaN; run by
// estimateAtEyeHits. Public for check/on_device.h's estimateAtEyeHitsOnDevice, which launches
// the two kernels itself (to download the queries) and must refuse the same parameters.
void validateEyeEstimateParams(const PclEyeEstimateParams& params);

}  // namespace pcl
