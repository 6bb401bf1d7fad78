#include "pipeline/trace_photons.h"

#include "core/error.h"

namespace pcl {

uint32_t photonSlotsPerPath(const PclPhotonParams& params) {
    return params.pass == PCL_PASS_CAUSTIC ? 1u : params.maxDepth;
}

cl::Event tracePhotons(Device& device, const DeviceScene& scene, const PclPhotonParams& params,
                       const cl::Buffer& rays, cl::Buffer& slots, cl::Buffer& counts, cl::Buffer& ends) {
    if (params.maxDepth < 1 || params.maxDepth > 255)
        throw InputError("photon pass: maxDepth " + std::to_string(params.maxDepth) +
                         ": expected 1..255 (the bounce count is a byte of the photon record)");
    auto kernel = device.kernel<PclPhotonParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                                cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer>(
        "trace_photons", params.pass == PCL_PASS_CAUSTIC ? "trace_photons_caustic" : "trace_photons_global",
        scene.geometry.programOptions());
    return device.launchLocal("trace_photons", kernel, photonGlobalRange(params.batchSize),
                              cl::NDRange(kPhotonGroup), params, rays,
                         scene.geometry.nodes, scene.geometry.packets, scene.geometry.spheres, scene.primInfo,
                         scene.materials, slots, counts, ends);
}

PhotonTraceResult tracePhotonsOnDevice(Device& device, const SceneGeometry& geometry,
                                       const SceneBuffers& buffers, const std::vector<PclPhotonRay>& rays,
                                       const PclPhotonParams& params) {
    if (rays.size() != params.batchSize)
        throw InputError("tracePhotonsOnDevice: " + std::to_string(rays.size()) + " rays for a batch of " +
                         std::to_string(params.batchSize));
    DeviceScene scene(device, geometry, buffers);
    PhotonTraceResult r;
    r.slotsPerPath = photonSlotsPerPath(params);
    const size_t n = params.batchSize;
    cl::Buffer rayBuf = device.upload(rays);
    cl::Buffer slots = device.allocate<PclPhoton>(n * r.slotsPerPath);
    cl::Buffer counts = device.allocate<uint32_t>(n);
    cl::Buffer ends = device.allocate<uint32_t>(n);
    tracePhotons(device, scene, params, rayBuf, slots, counts, ends);
    r.slots = device.download<PclPhoton>(slots, n * r.slotsPerPath);
    r.counts = device.download<uint32_t>(counts, n);
    r.ends = device.download<uint32_t>(ends, n);
    for (size_t i = 0; i < n; ++i)
        for (uint32_t k = r.counts[i]; k < r.slotsPerPath; ++k) r.slots[i * r.slotsPerPath + k] = PclPhoton{};
    return r;
}

}  // namespace pcl
