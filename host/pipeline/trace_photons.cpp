#include "pipeline/trace_photons.h"

#include <algorithm>

#include "core/error.h"

namespace pcl {

uint32_t defaultPhotonBatch(const Device& device, uint32_t slotsPerPath) {
    return defaultPhotonBatch(device.info().maxAlloc, (device.info().type & CL_DEVICE_TYPE_GPU) != 0, slotsPerPath);
}

uint32_t defaultPhotonBatch(size_t maxAlloc, bool gpu, uint32_t slotsPerPath) {
    size_t budget = std::min<size_t>(size_t(256) << 20, maxAlloc / 4);
    size_t paths = budget / (size_t(std::max(1u, slotsPerPath)) * sizeof(PclPhoton));
    // A GPU needs many paths in flight; a CPU is as busy with fewer, and a smaller slot buffer
    // spends less on first-touch page faults (PoCL: ~10 % faster at 2^16 than at 2^18).
    paths = std::min<size_t>(paths, size_t(1) << (gpu ? 18 : 16));
    // Whole 1024s; below that (a buffer cap of a few MiB) whole work-groups, so the slot buffer
    // stays under the cap.
    paths = paths >= 1024 ? paths / 1024 * 1024 : std::max<size_t>(paths / kPhotonGroup * kPhotonGroup, kPhotonGroup);
    return uint32_t(paths);
}

uint32_t photonSlotsPerPath(const PclPhotonParams& params) {
    return params.maxDepth;
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
                              cl::NDRange(kPhotonGroup), params, rays, scene.geometry.nodes,
                              scene.geometry.packets, scene.geometry.spheres, scene.primInfo, scene.materials,
                              slots, counts, ends);
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
    const size_t n = params.batchSize, S = r.slotsPerPath;
    r.slots.resize(n * S);
    r.counts.resize(n);
    r.ends.resize(n);
    // In launches of at most a pass's batch, so a large check neither outgrows a buffer nor
    // runs one long launch; photon indices (and so the random numbers) are unchanged.
    const size_t chunk = std::min<size_t>(std::max<size_t>(n, 1), defaultPhotonBatch(device, uint32_t(S)));
    cl::Buffer rayBuf = device.allocate<PclPhotonRay>(chunk, CL_MEM_READ_WRITE, "photon pass: rays");
    cl::Buffer slots = device.allocate<PclPhoton>(chunk * S, CL_MEM_READ_WRITE, "photon pass: slots");
    cl::Buffer counts = device.allocate<uint32_t>(chunk, CL_MEM_READ_WRITE, "photon pass: counts");
    cl::Buffer ends = device.allocate<uint32_t>(chunk, CL_MEM_READ_WRITE, "photon pass: ends");
    for (size_t first = 0; first < n; first += chunk) {
        const size_t m = std::min(chunk, n - first);
        Device::guard("upload", [&] {
            device.queue().enqueueWriteBuffer(rayBuf, CL_TRUE, 0, m * sizeof(PclPhotonRay), rays.data() + first);
        });
        PclPhotonParams p = params;
        p.firstPhoton = params.firstPhoton + uint32_t(first);
        p.batchSize = uint32_t(m);
        tracePhotons(device, scene, p, rayBuf, slots, counts, ends);
        Device::guard("download", [&] {
            device.queue().enqueueReadBuffer(slots, CL_TRUE, 0, m * S * sizeof(PclPhoton), r.slots.data() + first * S);
            device.queue().enqueueReadBuffer(counts, CL_TRUE, 0, m * sizeof(uint32_t), r.counts.data() + first);
            device.queue().enqueueReadBuffer(ends, CL_TRUE, 0, m * sizeof(uint32_t), r.ends.data() + first);
        });
    }
    for (size_t i = 0; i < n; ++i)
        for (uint32_t k = r.counts[i]; k < S; ++k) r.slots[i * S + k] = PclPhoton{};
    return r;
}

}  // namespace pcl
