#include "pipeline/direct_light.h"

#include "core/error.h"

namespace pcl {

AreaLightTable buildAreaLightTable(const SceneBuffers& buffers, size_t primitiveCount) {
    AreaLightTable t;
    t.lightOfPrim.assign(primitiveCount, PCL_NO_HIT);
    const size_t n = buffers.lights.size();
    std::vector<double> s(n, 0.0);
    double total = 0.0;
    float totalF = 0.0f;
    size_t last = n;
    for (size_t l = 0; l < n; ++l) {
        const PclLight& L = buffers.lights[l];
        if (L.type != PCL_LIGHT_TRIANGLE) continue;
        if (L.prim < primitiveCount) t.lightOfPrim[L.prim] = uint32_t(l);
        // The kernel's s_L: (Φr + Φg + Φb)/3 in float; the total summed in float in light order.
        const float sf = (L.power[0] + L.power[1] + L.power[2]) / 3.0f;
        if (!(sf > 0.0f)) continue;
        s[l] = sf;
        total += sf;
        totalF += sf;
        last = l;
        ++t.areaLights;
    }
    t.cdf.assign(n, 0.0f);
    double running = 0.0;
    for (size_t l = 0; l < n; ++l) {
        running += s[l];
        t.cdf[l] = total > 0.0 ? float(running / total) : 0.0f;
        if (l >= last && last < n) t.cdf[l] = 1.0f;
    }
    t.total = t.areaLights ? totalF : 0.0f;
    return t;
}

DeviceAreaLights::DeviceAreaLights(Device& device, const AreaLightTable& table)
    : cdf(device.upload(table.cdf, CL_MEM_READ_ONLY, "direct light: area light cdf")),
      lightOfPrim(device.upload(table.lightOfPrim, CL_MEM_READ_ONLY, "direct light: light of primitive")),
      total(table.total),
      areaLights(table.areaLights) {}

float misWeight(uint32_t nThis, float pThis, uint32_t nOther, float pOther) {
    const float a = float(nThis) * pThis, b = float(nOther) * pOther;
    const float a2 = a * a, s = a2 + b * b;
    return s > 0.0f ? a2 / s : 0.0f;
}

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
    return p;
}

cl::Event directLight(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                      const PclDirectParams& params, const cl::Buffer& hits, cl::Buffer& radiance) {
    if (params.histogramCells != 0)
        throw InputError("direct light: histogramCells " + std::to_string(params.histogramCells) +
                         " without histograms: expected the overload that takes them, or 0");
    const cl::Buffer none = device.allocate<float>(1, CL_MEM_READ_ONLY, "direct light: no histograms");
    return directLight(device, scene, lights, params, hits, none, radiance);
}

cl::Event directLight(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                      const PclDirectParams& params, const cl::Buffer& hits, const cl::Buffer& histograms,
                      cl::Buffer& radiance) {
    auto kernel = device.kernel<PclDirectParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                                cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer>(
        "direct_light", "direct_light", scene.geometry.programOptions());
    return device.launchLocal("direct_light", kernel, photonGlobalRange(params.sampleCount), cl::NDRange(kPhotonGroup),
                              params, hits, scene.geometry.nodes, scene.geometry.packets, scene.geometry.spheres,
                              scene.primInfo, scene.materials, scene.lights, lights.cdf, histograms, radiance);
}

std::vector<PclRadiance> directLightOnDevice(Device& device, const SceneGeometry& geometry,
                                             const SceneBuffers& buffers, const std::vector<PclEyeHit>& hits,
                                             const PclDirectParams& params, const std::vector<float>* histograms) {
    if (hits.size() != params.sampleCount)
        throw InputError("directLightOnDevice: " + std::to_string(hits.size()) + " records for " +
                         std::to_string(params.sampleCount));
    const size_t cells = size_t(params.histogramCells) * params.histogramCells;
    if (cells > 0 && (!histograms || histograms->size() != hits.size() * cells))
        throw InputError("directLightOnDevice: histogramCells " + std::to_string(params.histogramCells) +
                         " needs records × G² histogram entries");
    DeviceScene scene(device, geometry, buffers);
    DeviceAreaLights lights(device, buildAreaLightTable(buffers, geometry.primitiveCount()));
    cl::Buffer hitBuf = device.upload(hits, CL_MEM_READ_ONLY, "direct light: eye hits");
    cl::Buffer hist = cells > 0 ? device.upload(*histograms, CL_MEM_READ_ONLY, "direct light: histograms")
                                : device.allocate<float>(1, CL_MEM_READ_ONLY, "direct light: no histograms");
    cl::Buffer out = device.allocate<PclRadiance>(hits.size(), CL_MEM_READ_WRITE, "direct light: radiance");
    directLight(device, scene, lights, params, hitBuf, hist, out);
    return device.download<PclRadiance>(out, hits.size());
}

}  // namespace pcl
