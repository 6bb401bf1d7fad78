#include "pipeline/direct_light.h"

#include "core/error.h"
#include "pipeline/pass_strata.h"
#include "shared/rng.h"

namespace pcl {

DeviceAreaLights::DeviceAreaLights(Device& device, const AreaLightTable& table)
    : cdf(device.upload(table.cdf, CL_MEM_READ_ONLY, "direct light: area light cdf")),
      lightOfPrim(device.upload(table.lightOfPrim, CL_MEM_READ_ONLY, "direct light: light of primitive")),
      total(table.total), areaLights(table.areaLights) {}

PclDirectParams directParams(const PclEyeParams& eye, const SceneGeometry& geometry, const SceneBuffers& buffers,
                             const AreaLightTable& table, uint32_t lightSamples, uint32_t gatherRays) {
    PclDirectParams p{};
    p.seedLo = eye.seedLo;
    p.seedHi = eye.seedHi;
    p.samplesPerPixel = eye.samplesPerPixel;
    p.sampleCount = eye.sampleCount;
    p.lightCount = uint32_t(buffers.lights.size());
    p.triangleCount = geometry.triangleCount();
    p.lightSamples = lightSamples;
    p.gatherRays = gatherRays;
    p.areaPowerTotal = table.total;
    p.rayEpsilon = buffers.rayEpsilon;
    p.hasMedia = buffers.hasMedia ? 1u : 0u;
    return p;
}

cl::Event directLight(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                      const PclDirectParams& params, const cl::Buffer& hits, cl::Buffer& radiance) {
    if (params.histogramCells != 0)
        throw InternalError("direct light: histogramCells " + std::to_string(params.histogramCells) +
                            " without histograms: expected the overload that takes them, or 0");
    const cl::Buffer none = device.allocate<float>(1, CL_MEM_READ_ONLY, "direct light: no histograms");
    return directLight(device, scene, lights, params, hits, none, radiance);
}

cl::Event directLight(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                      const PclDirectParams& params, const cl::Buffer& hits, const cl::Buffer& histograms,
                      cl::Buffer& radiance) {
    // PCL_TEXTURED: triangle lights may have emission textures (kernels/shared/texture.h).
    auto kernel = device.kernel<PclDirectParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                                cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, PclEnvironment,
                                cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer>(
        "direct_light", "direct_light", scene.geometry.programOptions() + (scene.textured ? " -DPCL_TEXTURED=1" : ""));
    // Two patterns: the triangle lights' points, then the sky's directions.
    const cl::Buffer strata =
        uploadPassStrata(device, params.seedLo, params.seedHi, PCL_RNG_STREAM_LIGHT, PCL_LIGHT_PATTERN_BOUNCE, 2,
                         params.samplesPerPixel * params.lightSamples, "direct light: the pass's strata");
    return device.launchLocal("direct_light", kernel, photonGlobalRange(params.sampleCount), cl::NDRange(kPhotonGroup),
                              params, hits, scene.geometry.nodes, scene.geometry.packets, scene.geometry.spheres,
                              scene.primInfo, scene.materials, scene.lights, lights.cdf, histograms, scene.media,
                              scene.primMedia, radiance, scene.sky, scene.skyData, scene.materialTextures, scene.texels,
                              scene.triangleUvs, strata);
}

}  // namespace pcl
