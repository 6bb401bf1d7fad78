#include "pipeline/connect_caustics.h"

#include <string>

#include "core/error.h"

namespace pcl {

PclConnectParams connectParams(const SceneGeometry& geometry, const SceneBuffers& buffers, uint32_t photonCount,
                               uint64_t passSeed, bool hasTimes) {
    PclConnectParams p{};
    p.hasTimes = hasTimes ? 1u : 0u;
    p.seedLo = static_cast<uint32_t>(passSeed);
    p.seedHi = static_cast<uint32_t>(passSeed >> 32);
    p.photonCount = photonCount;
    p.triangleCount = geometry.triangleCount();
    p.rayEpsilon = buffers.rayEpsilon;
    p.findDistance = kConnectFindEpsilons * buffers.rayEpsilon;
    return p;
}

std::vector<PclSplat> connectCaustics(Device& device, const DeviceScene& scene, const PclConnectParams& params,
                                      const PclCameraParams& camera, const std::vector<PclPhoton>& photons,
                                      const std::vector<float>& times) {
    if (camera.timeSampling && !params.hasTimes)
        throw InternalError("connect caustics: the camera samples time, but the caustic records came without times");
    if (params.hasTimes && times.size() != photons.size())
        throw InternalError("connect caustics: " + std::to_string(times.size()) + " times for " +
                            std::to_string(photons.size()) + " records");
    if (params.photonCount != photons.size())
        throw InternalError("connect caustics: photonCount " + std::to_string(params.photonCount) + " for " +
                            std::to_string(photons.size()) + " records");
    if (photons.empty()) return {};
    const cl::Buffer records = device.upload(photons, CL_MEM_READ_ONLY, "connect caustics: photons");
    const cl::Buffer recordTimes =
        device.upload(params.hasTimes ? times : std::vector<float>{0.0f}, CL_MEM_READ_ONLY, "connect caustics: times");
    cl::Buffer out = device.allocate<PclSplat>(photons.size(), CL_MEM_WRITE_ONLY, "connect caustics: splats");
    auto kernel =
        device.kernel<PclConnectParams, PclCameraParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                      cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                      cl::Buffer>("connect_caustics", "connect_caustics", scene.programOptions());
    device.launchLocal("connect_caustics", kernel, photonGlobalRange(photons.size()), cl::NDRange(kPhotonGroup), params,
                       camera, records, recordTimes, scene.geometry.nodes, scene.geometry.packets,
                       scene.geometry.spheres, scene.primInfo, scene.materials, scene.materialTextures, scene.texels,
                       scene.triangleUvs, scene.triangleNormals, scene.normalMaps, scene.triangleTangents, out);
    return device.download<PclSplat>(out, photons.size());
}

}  // namespace pcl
