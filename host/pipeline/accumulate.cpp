#include "pipeline/accumulate.h"

#include "pipeline/device_scene.h"

namespace pcl {

cl::Event accumulateSamples(Device& device, const PclAccumulateParams& params, const cl::Buffer& hits,
                            const cl::Buffer& direct, const cl::Buffer& caustic, const cl::Buffer& indirect,
                            const cl::Buffer& volume0, const cl::Buffer& volume1, const cl::Buffer& spans,
                            cl::Buffer& radiance) {
    auto kernel = device.kernel<PclAccumulateParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                                cl::Buffer, cl::Buffer, cl::Buffer>("accumulate", "accumulate_samples");
    return device.launchLocal("accumulate", kernel, photonGlobalRange(params.sampleCount), cl::NDRange(kPhotonGroup),
                              params, hits, direct, caustic, indirect, volume0, volume1, spans, radiance);
}

}  // namespace pcl
