#include "pipeline/emit.h"

namespace pcl {

cl::Event emitPhotons(Device& device, const DeviceScene& scene, const cl::Buffer& lightFirst,
                      const PclPhotonParams& params, cl::Buffer& rays) {
    // PCL_TEXTURED: triangle lights may have emission textures (kernels/shared/texture.h).
    auto kernel = device.kernel<PclPhotonParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, PclEnvironment,
                                cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer>(
        "emit", "emit_photons", scene.textured ? "-DPCL_TEXTURED=1" : "");
    return device.launchLocal("emit", kernel, photonGlobalRange(params.batchSize), cl::NDRange(kPhotonGroup), params,
                              scene.lights, lightFirst, scene.projCells, rays, scene.sky, scene.skyData, scene.primInfo,
                              scene.materials, scene.materialTextures, scene.texels, scene.triangleUvs);
}

}  // namespace pcl
