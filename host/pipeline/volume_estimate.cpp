#include "pipeline/volume_estimate.h"

#include <cmath>
#include <string>

#include "core/error.h"
#include "core/math.h"
#include "pipeline/device_scene.h"

namespace pcl {

DeviceVolumeMap buildVolumeMap(Device& device, const std::vector<PclPhoton>& photons, float radius) {
    VolumeEstimateSettings s;
    s.radius = radius;
    validateVolumeEstimateInput(photons, s);
    DeviceVolumeMap map;
    map.radius = radius;
    map.photons = device.upload(photons, CL_MEM_READ_ONLY, "volume estimate: photons");
    // Cells of size r (the parameter is half the cell size): the slab walk visits about a third of
    // the photons it would with cells of 2r.
    map.grid = buildHashGrid(device, map.photons, photons.size(), hashGridParams(photons, 0.5f * radius));
    map.seconds = map.grid.keySeconds + map.grid.sortSeconds + map.grid.rangeSeconds;
    return map;
}

PclVolumeEstimateParams volumeEstimateParams(const DeviceVolumeMap& map, const VolumeEstimateSettings& settings,
                                             uint32_t sampleCount, uint32_t maxSegments, uint32_t mediumCount) {
    const PclGridParams& g = map.grid.params;
    const float r = settings.radius;
    if (!(r > 0.0f) || !(g.cellSize > 0.0f))
        throw InternalError("volume estimate: radius " + std::to_string(r) + " for a grid of cell size " +
                            std::to_string(g.cellSize) + ": expected both > 0");
    PclVolumeEstimateParams p{};
    p.ox = g.ox, p.oy = g.oy, p.oz = g.oz;
    p.cellSize = g.cellSize;
    p.invCellSize = g.invCellSize;
    p.tableSize = g.tableSize;
    p.photonCount = g.photonCount;
    p.radius = r;
    p.radius2 = r * r;
    p.kernelShape = beamKernelCode(settings.kernel);
    // ∫_disc K dA = 1: box 1/(π r²); biweight 3/(π r²) (1 − x²)², since ∫_0^1 (1 − x²)² 2x dx = 1/3.
    p.kernelScale = float((settings.kernel == BeamKernel::Box ? 1.0 : 3.0) / (kPiD * double(r) * double(r)));
    p.skipDirect = settings.skipDirect ? 1u : 0u;
    p.skipSpecularPaths = settings.skipSpecularPaths ? 1u : 0u;
    p.sampleCount = sampleCount;
    p.maxSegments = maxSegments;
    p.mediumCount = mediumCount;
    return p;
}

cl::Event volumeEstimateBeams(Device& device, const PclVolumeEstimateParams& params, const cl::Buffer& segments,
                              const cl::Buffer& segmentCounts, const cl::Buffer& media, const DeviceVolumeMap& map,
                              cl::Buffer& volume) {
    auto kernel = device.kernel<PclVolumeEstimateParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                                cl::Buffer, cl::Buffer, cl::Buffer>("volume_estimate", "volume_estimate_beams");
    return device.launchLocal("volume_estimate", kernel, photonGlobalRange(params.sampleCount),
                              cl::NDRange(kPhotonGroup), params, segments, segmentCounts, media, map.photons,
                              map.grid.points, map.grid.cellStart, map.grid.cellEnd, volume);
}

cl::Buffer estimateVolumeRadiance(Device& device, const DeviceVolumeMap& map, const PclVolumeEstimateParams& params,
                                  const cl::Buffer& segments, const cl::Buffer& segmentCounts, const cl::Buffer& media,
                                  double* seconds) {
    cl::Buffer volume =
        device.allocate<PclRadiance>(params.sampleCount, CL_MEM_READ_WRITE, "volume estimate: radiance");
    double s = 0.0;
    if (params.sampleCount > 0) {
        cl::Event e = volumeEstimateBeams(device, params, segments, segmentCounts, media, map, volume);
        e.wait();
        s = Device::elapsedSeconds(e);
    }
    if (seconds) *seconds = s;
    return volume;
}

std::vector<PclRadiance> volumeEstimateOnDevice(Device& device, const std::vector<PclPhoton>& photons,
                                                const VolumeEstimateSettings& settings, const VolumeSegments& segments,
                                                const std::vector<PclMedium>& media, double* seconds) {
    validateVolumeSegments(segments, media.size());
    const DeviceVolumeMap map = buildVolumeMap(device, photons, settings.radius);
    const PclVolumeEstimateParams p =
        volumeEstimateParams(map, settings, segments.sampleCount, segments.maxSegments, uint32_t(media.size()));
    const cl::Buffer segBuf = device.upload(segments.segments, CL_MEM_READ_ONLY, "volume estimate: segments");
    const cl::Buffer countBuf = device.upload(segments.counts, CL_MEM_READ_ONLY, "volume estimate: segment counts");
    const cl::Buffer mediaBuf = device.upload(media, CL_MEM_READ_ONLY, "volume estimate: media");
    double kernelSeconds = 0.0;
    const cl::Buffer volume = estimateVolumeRadiance(device, map, p, segBuf, countBuf, mediaBuf, &kernelSeconds);
    if (seconds) *seconds = map.seconds + kernelSeconds;
    return device.download<PclRadiance>(volume, segments.sampleCount);
}

}  // namespace pcl
