#include "pipeline/emit.h"

namespace pcl {

cl::Event emitPhotons(Device& device, const DeviceScene& scene, const cl::Buffer& lightFirst,
                      const PclPhotonParams& params, cl::Buffer& rays) {
    auto kernel = device.kernel<PclPhotonParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer>(
        "emit", "emit_photons");
    return device.launchLocal("emit", kernel, photonGlobalRange(params.batchSize), cl::NDRange(kPhotonGroup), params, scene.lights, lightFirst,
                         scene.projCells, rays);
}

std::vector<PclPhotonRay> emitOnDevice(Device& device, const SceneGeometry& geometry,
                                       const SceneBuffers& buffers,
                                       const std::vector<uint32_t>& lightFirst,
                                       const PclPhotonParams& params) {
    DeviceScene scene(device, geometry, buffers);
    cl::Buffer first = device.upload(lightFirst, CL_MEM_READ_ONLY, "photon pass: light offsets");
    cl::Buffer rays = device.allocate<PclPhotonRay>(params.batchSize, CL_MEM_READ_WRITE, "photon pass: rays");
    emitPhotons(device, scene, first, params, rays);
    return device.download<PclPhotonRay>(rays, params.batchSize);
}

}  // namespace pcl
