#include "pipeline/volume_estimate.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "core/math.h"
#include "pipeline/device_scene.h"
#include "pipeline/kdtree.h"
#include "pipeline/knn.h"

namespace pcl {

DeviceVolumeMap buildVolumeMap(Device& device, const std::vector<PclPhoton>& photons,
                               const VolumeEstimateSettings& settings) {
    validateVolumeEstimateInput(photons, settings);
    DeviceVolumeMap map;
    map.radius = settings.radius;
    const cl::Buffer photonBuf = device.upload(photons, CL_MEM_READ_ONLY, "volume estimate: photons");
    // Cells of size r (the parameter is half the cell size): the slab walk visits about a third of
    // the photons it would with cells of 2r.
    map.grid = buildHashGrid(device, photonBuf, photons.size(), hashGridParams(photons, 0.5f * settings.radius));
    map.seconds = map.grid.keySeconds + map.grid.sortSeconds + map.grid.rangeSeconds;
    const size_t n = std::max<size_t>(photons.size(), 1);
    map.beamPos = device.allocate<cl_float4>(n, CL_MEM_READ_WRITE, "volume estimate: packed positions");
    map.beamDir = device.allocate<cl_float4>(n, CL_MEM_READ_WRITE, "volume estimate: packed directions");
    map.beamPower = device.allocate<cl_float4>(n, CL_MEM_READ_WRITE, "volume estimate: packed power");
    if (photons.empty()) return map;
    const std::vector<float> radius2 = settings.photonRadius2.empty()
                                           ? std::vector<float>(photons.size(), settings.radius * settings.radius)
                                           : settings.photonRadius2;
    const cl::Buffer r2Buf = device.upload(radius2, CL_MEM_READ_ONLY, "volume estimate: radii²");
    const PclVolumeEstimateParams p = volumeEstimateParams(map, settings, 0, 0, 0);
    auto kernel =
        device.kernel<PclVolumeEstimateParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer>(
            "volume_estimate", "volume_pack_photons");
    cl::Event e = device.launchLocal("volume_estimate", kernel, photonGlobalRange(photons.size()),
                                     cl::NDRange(kPhotonGroup), p, photonBuf, r2Buf, map.grid.points, map.beamPos,
                                     map.beamDir, map.beamPower);
    e.wait();
    map.seconds += Device::elapsedSeconds(e);
    return map;
}

std::vector<float> volumeKthNeighbourDist2(Device& device, const std::vector<PclPhoton>& photons, uint32_t k,
                                           float rMax, double* seconds) {
    if (k == 0 || k + 1 > PCL_KNN_MAX_K)
        throw InternalError("volume estimate: k = " + std::to_string(k) + " for per-photon radii, expected 1.." +
                            std::to_string(PCL_KNN_MAX_K - 1));
    std::vector<float> out(photons.size(), -1.0f);
    if (seconds) *seconds = 0.0;
    if (photons.size() <= 1) return out;
    const cl::Buffer photonBuf = device.upload(photons, CL_MEM_READ_ONLY, "volume estimate: radius photons");
    KdTreeTiming timing;
    const KnnKdTree tree = packKdTree(device, buildKdTree(device, photonBuf, photons.size(), &timing));
    std::vector<PclKnnQuery> queries(photons.size());
    for (size_t j = 0; j < photons.size(); ++j)
        queries[j] = PclKnnQuery{photons[j].x, photons[j].y, photons[j].z, rMax * rMax, k + 1, 0, 0, 0};
    const cl::Buffer queryBuf = device.upload(queries, CL_MEM_READ_ONLY, "volume estimate: radius queries");
    DeviceKnnOutput found;
    const double searchSeconds = knnSearchKdTree(device, tree, queryBuf, queries.size(), k + 1, found, rMax * rMax);
    const std::vector<uint32_t> counts = device.download<uint32_t>(found.counts, queries.size());
    const std::vector<float> r2 = device.download<float>(found.radius2, queries.size());
    // The photon itself is among its k + 1 nearest (at distance 0, or tied with a twin at 0).
    for (size_t j = 0; j < photons.size(); ++j)
        if (counts[j] == k + 1) out[j] = r2[j];
    if (seconds) *seconds = timing.sortSeconds + timing.otherSeconds + searchSeconds;
    return out;
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
    // ∫_disc K dA = 1: box 1/(π r_p²); biweight 3/(π r_p²) (1 − x²)², since ∫_0^1 (1 − x²)² 2x dx = 1/3.
    p.kernelNorm = float((settings.kernel == BeamKernel::Box ? 1.0 : 3.0) / kPiD);
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
    auto kernel =
        device.kernel<PclVolumeEstimateParams, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer,
                      cl::Buffer, cl::Buffer, cl::Buffer>("volume_estimate", "volume_estimate_beams");
    return device.launchLocal("volume_estimate", kernel, photonGlobalRange(params.sampleCount),
                              cl::NDRange(kPhotonGroup), params, segments, segmentCounts, media, map.beamPos,
                              map.beamDir, map.beamPower, map.grid.cellStart, map.grid.cellEnd, volume);
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
    const DeviceVolumeMap map = buildVolumeMap(device, photons, settings);
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
