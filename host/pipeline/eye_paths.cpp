#include "pipeline/eye_paths.h"

#include "core/error.h"

namespace pcl {

PclEyeParams eyeParams(const PclCameraParams& camera, const SceneGeometry& geometry, const SceneBuffers& buffers,
                       const AreaLightTable& table, uint32_t maxDepth) {
    if (maxDepth < 1 || maxDepth > 64)
        throw InternalError("eye paths: maxDepth " + std::to_string(maxDepth) + ": expected 1..64");
    PclEyeParams p{};
    p.seedLo = camera.seedLo;
    p.seedHi = camera.seedHi;
    p.samplesPerPixel = camera.strata * camera.strata;
    p.firstSample = camera.firstSample;
    p.sampleCount = camera.sampleCount;
    p.triangleCount = geometry.triangleCount();
    p.maxDepth = maxDepth;
    p.rayEpsilon = buffers.rayEpsilon;
    p.lightCount = uint32_t(buffers.lights.size());
    p.areaPowerTotal = table.total;
    return p;
}

cl::Event traceEyePaths(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                        const PclEyeParams& params, const cl::Buffer& rays, cl::Buffer& hits) {
    if (params.samplesPerPixel == 0 || params.maxDepth < 1 || params.maxDepth > 64)
        throw InternalError("eye paths: samplesPerPixel " + std::to_string(params.samplesPerPixel) + ", maxDepth " +
                            std::to_string(params.maxDepth) + ": expected ≥ 1 and 1..64");
    auto kernel =
        device.kernel<PclEyeParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                      cl::Buffer, cl::Buffer, cl::Buffer>("eye_paths", "eye_paths", scene.geometry.programOptions());
    return device.launchLocal("eye_paths", kernel, photonGlobalRange(params.sampleCount), cl::NDRange(kPhotonGroup),
                              params, rays, scene.geometry.nodes, scene.geometry.packets, scene.geometry.spheres,
                              scene.primInfo, scene.materials, scene.lights, lights.cdf, lights.lightOfPrim, hits);
}

}  // namespace pcl
