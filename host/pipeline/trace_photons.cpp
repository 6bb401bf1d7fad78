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

uint32_t photonSlotsPerPath(const PclPhotonParams& params) { return params.maxDepth; }

cl::Event tracePhotons(Device& device, const DeviceScene& scene, const PclPhotonParams& params, const cl::Buffer& rays,
                       cl::Buffer& slots, cl::Buffer& counts, cl::Buffer& ends, cl::Buffer& volumeSlots,
                       cl::Buffer& volumeCounts) {
    if (params.maxDepth < 1 || params.maxDepth > 255)
        throw InternalError("photon pass: maxDepth " + std::to_string(params.maxDepth) +
                            ": expected 1..255 (the bounce count is a byte of the photon record)");
    auto kernel = device.kernel<PclPhotonParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                                cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                                cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer>(
        "trace_photons", params.pass == PCL_PASS_CAUSTIC ? "trace_photons_caustic" : "trace_photons_global",
        scene.programOptions());
    return device.launchLocal("trace_photons", kernel, photonGlobalRange(params.batchSize), cl::NDRange(kPhotonGroup),
                              params, rays, scene.geometry.nodes, scene.geometry.packets, scene.geometry.spheres,
                              scene.primInfo, scene.materials, slots, counts, ends, scene.media, scene.primMedia,
                              scene.lightMedia, volumeSlots, volumeCounts, scene.materialTextures, scene.texels,
                              scene.triangleUvs, scene.triangleNormals, scene.normalMaps, scene.triangleTangents);
}

}  // namespace pcl
