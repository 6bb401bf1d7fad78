#include "pipeline/emit.h"

namespace pcl {

cl::Event emitPhotons(Device& device, const DeviceScene& scene, const cl::Buffer& lightFirst,
                      const PclPhotonParams& params, cl::Buffer& rays) {
    auto kernel =
        device.kernel<PclPhotonParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, PclEnvironment, cl::Buffer>(
            "emit", "emit_photons");
    return device.launchLocal("emit", kernel, photonGlobalRange(params.batchSize), cl::NDRange(kPhotonGroup), params,
                              scene.lights, lightFirst, scene.projCells, rays, scene.sky, scene.skyData);
}

}  // namespace pcl
