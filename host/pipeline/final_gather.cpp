#include "pipeline/final_gather.h"

#include <cmath>

#include "core/error.h"
#include "pipeline/pass_strata.h"
#include "pipeline/query_order.h"
#include "shared/rng.h"

namespace pcl {

PclGatherParams gatherParams(const PclDirectParams& direct, uint32_t gatherRays, uint32_t k, float maxRadius2,
                             uint32_t maxSpecular) {
    if (gatherRays < 1)
        throw InternalError("final gather: 0 gather rays: expected at least 1 (direct visualisation reads the global "
                            "map at the eye hits instead)");
    if (direct.gatherRays != gatherRays)
        throw InternalError("final gather: " + std::to_string(gatherRays) +
                            " gather rays, but direct light weighs its "
                            "samples against " +
                            std::to_string(direct.gatherRays) + ": expected the same N");
    if (k < 1 || k > PCL_KNN_MAX_K)
        throw InternalError("final gather: k " + std::to_string(k) + ": expected 1.." + std::to_string(PCL_KNN_MAX_K));
    if (!(maxRadius2 >= 0.0f))
        throw InternalError("final gather: maxRadius² " + std::to_string(maxRadius2) + ": expected ≥ 0");
    PclGatherParams p{};
    p.seedLo = direct.seedLo;
    p.seedHi = direct.seedHi;
    p.samplesPerPixel = direct.samplesPerPixel;
    p.sampleCount = direct.sampleCount;
    p.gatherRays = gatherRays;
    p.triangleCount = direct.triangleCount;
    p.lightCount = direct.lightCount;
    p.maxSpecular = maxSpecular;
    p.lightSamples = direct.lightSamples;
    p.k = k;
    p.maxRadius2 = maxRadius2;
    p.areaPowerTotal = direct.areaPowerTotal;
    p.rayEpsilon = direct.rayEpsilon;
    p.irradianceStride = 8;
    return p;
}

static size_t gatherRayCount(const PclGatherParams& p) { return size_t(p.sampleCount) * p.gatherRays; }

cl::Event traceGatherRays(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                          const PclGatherParams& params, const cl::Buffer& hits, cl::Buffer& queries,
                          cl::Buffer& gathered) {
    if (params.histogramCells != 0)
        throw InternalError("final gather: histogramCells " + std::to_string(params.histogramCells) +
                            " without histograms: expected the overload that takes them, or 0");
    const cl::Buffer none = device.allocate<float>(1, CL_MEM_READ_ONLY, "final gather: no histograms");
    return traceGatherRays(device, scene, lights, params, hits, none, queries, gathered);
}

cl::Event traceGatherRays(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                          const PclGatherParams& params, const cl::Buffer& hits, const cl::Buffer& histograms,
                          cl::Buffer& queries, cl::Buffer& gathered) {
    if (gatherRayCount(params) > 0xFFFFFFFFull)
        throw InternalError("final gather: " + std::to_string(gatherRayCount(params)) +
                            " gather rays in one launch: expected below 2^32 (launch fewer records)");
    if (params.histogramCells > PCL_GATHER_MAX_CELLS)
        throw InternalError("final gather: histogramCells " + std::to_string(params.histogramCells) +
                            ": expected 0..16");
    if (!(params.closeDistance >= 0.0f))
        throw InternalError("final gather: closeDistance " + std::to_string(params.closeDistance) + ": expected ≥ 0");
    auto kernel =
        device.kernel<PclGatherParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                      cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, PclEnvironment,
                      cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer>(
            "final_gather", "final_gather_trace", scene.programOptions());
    const cl::Buffer strata = uploadPassStrata(device, params.seedLo, params.seedHi, PCL_RNG_STREAM_GATHER,
                                               PCL_GATHER_PATTERN_BOUNCE, 1, params.samplesPerPixel * params.gatherRays,
                                               "final gather: the pass's strata");
    return device.launchLocal("final_gather", kernel, photonGlobalRange(gatherRayCount(params)),
                              cl::NDRange(kPhotonGroup), params, hits, scene.geometry.nodes, scene.geometry.packets,
                              scene.geometry.spheres, scene.primInfo, scene.materials, scene.lights, lights.lightOfPrim,
                              lights.cdf, histograms, queries, gathered, scene.sky, scene.skyData,
                              scene.materialTextures, scene.texels, scene.triangleUvs, scene.triangleNormals,
                              scene.normalMaps, scene.triangleTangents, strata);
}

cl::Buffer buildGatherHistograms(Device& device, const PhotonMapOnDevice& global, const PclGatherParams& params,
                                 const cl::Buffer& hits) {
    const uint32_t G = params.histogramCells;
    if (G < 1 || G > PCL_GATHER_MAX_CELLS)
        throw InternalError("final gather: histogramCells " + std::to_string(G) + ": expected 1..16");
    const size_t n = params.sampleCount;
    cl::Buffer queries = device.allocate<PclKnnQuery>(n, CL_MEM_READ_WRITE, "final gather: histogram queries");
    auto q = device.kernel<PclGatherParams, cl::Buffer, cl::Buffer>("final_gather", "final_gather_histogram_queries");
    device.launchLocal("final_gather", q, photonGlobalRange(n), cl::NDRange(kPhotonGroup), params, hits, queries);
    DeviceKnnOutput knn;
    global.search(device, queries, n, params.k, knn);
    cl::Buffer histograms = device.allocate<float>(n * G * G, CL_MEM_READ_WRITE, "final gather: histograms");
    auto h = device.kernel<PclGatherParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl_uint, cl::Buffer>(
        "final_gather", "final_gather_histogram");
    device.launchLocal("final_gather", h, photonGlobalRange(n), cl::NDRange(kPhotonGroup), params, hits,
                       global.photons(), knn.counts, knn.indices, cl_uint(knn.stride), histograms);
    device.finish();
    return histograms;
}

cl::Event resolveGather(Device& device, const PclGatherParams& params, const cl::Buffer& hits,
                        const cl::Buffer& gathered, const cl::Buffer& irradiance, cl::Buffer& radiance) {
    auto kernel = device.kernel<PclGatherParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer>(
        "final_gather", "final_gather_resolve", "");
    return device.launchLocal("final_gather", kernel, photonGlobalRange(params.sampleCount), cl::NDRange(kPhotonGroup),
                              params, hits, gathered, irradiance, radiance);
}

GatherTiming finalGather(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                         PclGatherParams params, const cl::Buffer& hits, IrradianceSource& source,
                         cl::Buffer& radiance) {
    if (params.histogramCells != 0)
        throw InternalError("final gather: histogramCells " + std::to_string(params.histogramCells) +
                            " without histograms: expected the overload that takes them, or 0");
    const cl::Buffer none = device.allocate<float>(1, CL_MEM_READ_ONLY, "final gather: no histograms");
    return finalGather(device, scene, lights, params, hits, none, source, radiance);
}

GatherTiming finalGather(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                         PclGatherParams params, const cl::Buffer& hits, const cl::Buffer& histograms,
                         IrradianceSource& source, cl::Buffer& radiance) {
    GatherTiming t;
    params.irradianceStride = source.strideFloats;
    const size_t n = gatherRayCount(params);
    cl::Buffer queries = device.allocate<PclEstimateQuery>(n, CL_MEM_READ_WRITE, "final gather: queries");
    cl::Buffer gathered = device.allocate<PclGatherHit>(n, CL_MEM_READ_WRITE, "final gather: gathered rays");
    cl::Event e = traceGatherRays(device, scene, lights, params, hits, histograms, queries, gathered);
    device.finish();
    if (e()) t.traceSeconds = Device::elapsedSeconds(e);
    const double before = source.seconds;
    // The gather rays' hits lie all over the scene: read in that order the map's searches wait
    // on memory. Sorted by cell (r_max / 4) first, the lookups ran 4-6x faster on cornell-box
    // (the sort costs a fraction of that); the results go back to ray order unchanged.
    const float cell =
        params.maxRadius2 > 0.0f && std::isfinite(params.maxRadius2) ? std::sqrt(params.maxRadius2) / 4.0f : 1.0f;
    const QueryOrder order = orderQueries(device, queries, n, cell);
    const cl::Buffer sortedIrradiance = source.evaluate(device, order.sorted, n);
    cl::Buffer irradiance =
        device.allocate<float>(n * source.strideFloats, CL_MEM_READ_WRITE, "final gather: irradiance");
    scatterResults(device, order, sortedIrradiance, source.strideFloats, irradiance);
    t.irradianceSeconds = source.seconds - before;
    e = resolveGather(device, params, hits, gathered, irradiance, radiance);
    device.finish();
    if (e()) t.resolveSeconds = Device::elapsedSeconds(e);
    return t;
}

}  // namespace pcl
