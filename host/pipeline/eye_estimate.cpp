#include "pipeline/eye_estimate.h"

#include "core/error.h"
#include "pipeline/device_scene.h"

namespace pcl {

cl::Event eyeEstimateQueries(Device& device, const PclEyeEstimateParams& params, const cl::Buffer& hits,
                             const cl::Buffer& primInfo, cl::Buffer& queries) {
    auto kernel =
        device.kernel<PclEyeEstimateParams, cl::Buffer, cl::Buffer, cl::Buffer>("eye_estimate", "eye_estimate_queries");
    return device.launchLocal("eye_estimate", kernel, photonGlobalRange(params.sampleCount), cl::NDRange(kPhotonGroup),
                              params, hits, primInfo, queries);
}

cl::Event eyeEstimateResolve(Device& device, const PclEyeEstimateParams& params, const cl::Buffer& hits,
                             const cl::Buffer& irradiance, cl::Buffer& radiance) {
    auto kernel =
        device.kernel<PclEyeEstimateParams, cl::Buffer, cl::Buffer, cl::Buffer>("eye_estimate", "eye_estimate_resolve");
    return device.launchLocal("eye_estimate", kernel, photonGlobalRange(params.sampleCount), cl::NDRange(kPhotonGroup),
                              params, hits, irradiance, radiance);
}

void validateEyeEstimateParams(const PclEyeEstimateParams& p) {
    if (p.k < 1 || p.k > PCL_KNN_MAX_K)
        throw InternalError("eye estimate: k " + std::to_string(p.k) + ": expected 1.." +
                            std::to_string(PCL_KNN_MAX_K));
    if (!(p.maxRadius2 >= 0.0f))
        throw InternalError("eye estimate: maxRadius² " + std::to_string(p.maxRadius2) + ": expected ≥ 0");
}

double estimateAtEyeHits(Device& device, PclEyeEstimateParams params, const cl::Buffer& hits,
                         const cl::Buffer& primInfo, IrradianceSource& source, cl::Buffer& radiance) {
    validateEyeEstimateParams(params);
    params.irradianceStride = source.strideFloats;
    cl::Buffer queries =
        device.allocate<PclEstimateQuery>(params.sampleCount, CL_MEM_READ_WRITE, "eye estimate: queries");
    double seconds = 0.0;
    cl::Event e = eyeEstimateQueries(device, params, hits, primInfo, queries);
    device.finish();
    if (e()) seconds += Device::elapsedSeconds(e);
    const double before = source.seconds;
    cl::Buffer irradiance = source.evaluate(device, queries, params.sampleCount);
    seconds += source.seconds - before;
    e = eyeEstimateResolve(device, params, hits, irradiance, radiance);
    device.finish();
    if (e()) seconds += Device::elapsedSeconds(e);
    return seconds;
}

}  // namespace pcl
