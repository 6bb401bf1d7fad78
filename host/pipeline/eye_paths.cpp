#include "pipeline/eye_paths.h"

#include "core/error.h"

namespace pcl {

PclEyeParams eyeParams(const PclCameraParams& camera, const SceneGeometry& geometry, const SceneBuffers& buffers,
                       const AreaLightTable& table, uint32_t maxDepth, uint32_t volumeSegments) {
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
    if (buffers.hasMedia) {
        if (volumeSegments < 1) throw InternalError("eye paths: volumeSegments 0 in a scene with media: expected ≥ 1");
        p.cameraMedium = buffers.cameraMedium;
        p.volumeSegments = volumeSegments;
    } else {
        p.cameraMedium = PCL_NO_MEDIUM;
        p.volumeSegments = 0;
    }
    for (int c = 0; c < 3; ++c) p.sceneCentre[c] = buffers.sceneCentre[c];
    p.sceneRadius = buffers.sceneRadius;
    return p;
}

cl::Event traceEyePaths(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                        const PclEyeParams& params, const cl::Buffer& rays, cl::Buffer& hits) {
    if (params.volumeSegments != 0)
        throw InternalError("eye paths: volumeSegments " + std::to_string(params.volumeSegments) +
                            " without segment buffers: expected the overload that takes them, or 0");
    cl::Buffer segments = device.allocate<PclVolumeSegment>(1, CL_MEM_READ_WRITE, "eye paths: no segments");
    cl::Buffer counts = device.allocate<uint32_t>(1, CL_MEM_READ_WRITE, "eye paths: no segment counts");
    return traceEyePaths(device, scene, lights, params, rays, hits, segments, counts);
}

cl::Event traceEyePaths(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                        const PclEyeParams& params, const cl::Buffer& rays, cl::Buffer& hits, cl::Buffer& segments,
                        cl::Buffer& segmentCounts) {
    if (params.samplesPerPixel == 0 || params.maxDepth < 1 || params.maxDepth > 64)
        throw InternalError("eye paths: samplesPerPixel " + std::to_string(params.samplesPerPixel) + ", maxDepth " +
                            std::to_string(params.maxDepth) + ": expected ≥ 1 and 1..64");
    auto kernel = device.kernel<PclEyeParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                                cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                                cl::Buffer, PclEnvironment, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                                cl::Buffer, cl::Buffer>("eye_paths", "eye_paths", scene.programOptions());
    return device.launchLocal("eye_paths", kernel, photonGlobalRange(params.sampleCount), cl::NDRange(kPhotonGroup),
                              params, rays, scene.geometry.nodes, scene.geometry.packets, scene.geometry.spheres,
                              scene.primInfo, scene.materials, scene.lights, lights.cdf, lights.lightOfPrim,
                              scene.media, scene.primMedia, hits, segments, segmentCounts, scene.sky, scene.skyData,
                              scene.materialTextures, scene.texels, scene.triangleUvs, scene.triangleNormals,
                              scene.normalMaps, scene.triangleTangents);
}

}  // namespace pcl
