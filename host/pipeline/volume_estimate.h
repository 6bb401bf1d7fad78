// The volume radiance estimate (kernels/volume_estimate.cl; kernels/README.md, "volume_estimate"):
// the beam radiance estimate of Jarosz, Zwicker & Jensen 2008 along the eye pass's medium
// segments, from one volume photon map searched through a hash grid of cell size r built on the
// device each pass (pipeline/hashgrid). The twin is host/reference/volume_estimate.h.
//
//   DeviceVolumeMap map = buildVolumeMap(device, maps.volume, settings);   // once per pass
//   PclVolumeEstimateParams p = volumeEstimateParams(map, settings, sampleCount, maxSegments, mediumCount);
//   cl::Buffer volume = estimateVolumeRadiance(device, map, p, segments, counts, mediaBuffer);  // per chunk
// or, on host vectors (tests, check): volumeEstimateOnDevice(device, photons, settings, segments, media).
// A render estimates each volume map on its own and adds them: the global volume map with
// skipSpecularPaths (and skipDirect when the eye pass adds single scattering by next-event
// estimation), plus the volume caustic map (kernels/README.md, "volume_estimate").
#pragma once
#include <cstdint>
#include <vector>

#include "device/device.h"
#include "pipeline/hashgrid.h"
#include "prep/volume_estimate_settings.h"
#include "shared/types.h"

namespace pcl {

// A volume map on the device with its hash grid (cell size r, the reach: volume_estimate.cl walks
// it in slabs) and the photons packed in the grid's order by volume_pack_photons.
struct DeviceVolumeMap {
    DeviceHashGrid grid;
    cl::Buffer beamPos, beamDir, beamPower;  // float4 each per grid entry (volume_estimate.cl)
    float radius = 0.0f;
    double seconds = 0.0;  // device time of the grid build and the packing
};

// Uploads the photons (and their radii, or r² for each), builds the grid and packs it for
// settings' kernel and skips. InternalError on input validateVolumeEstimateInput refuses.
DeviceVolumeMap buildVolumeMap(Device& device, const std::vector<PclPhoton>& photons,
                               const VolumeEstimateSettings& settings);

// Each photon's squared distance to its k-th nearest other photon of the map within rMax (the
// kd-tree search of pipeline/knn, k + 1 neighbours with the photon itself); −1 where fewer than
// k others lie within rMax. For clampVolumePhotonRadii2. seconds (optional): device time.
std::vector<float> volumeKthNeighbourDist2(Device& device, const std::vector<PclPhoton>& photons, uint32_t k,
                                           float rMax, double* seconds = nullptr);

// The launch parameters: the grid's, the reach r and r², the kernel and its normalisation over a
// unit disc, the skips. InternalError when the radius or the grid's cell size is not positive.
PclVolumeEstimateParams volumeEstimateParams(const DeviceVolumeMap& map, const VolumeEstimateSettings& settings,
                                             uint32_t sampleCount, uint32_t maxSegments, uint32_t mediumCount);

// Enqueues volume_estimate_beams: volume[i] for i < params.sampleCount.
cl::Event volumeEstimateBeams(Device& device, const PclVolumeEstimateParams& params, const cl::Buffer& segments,
                              const cl::Buffer& segmentCounts, const cl::Buffer& media, const DeviceVolumeMap& map,
                              cl::Buffer& volume);

// The estimate on device buffers (the eye pass's segments and counts, the scene's media):
// allocates only the radiance ("volume estimate: radiance", params.sampleCount records) and
// waits for it. seconds (optional) receives the kernel's device time.
cl::Buffer estimateVolumeRadiance(Device& device, const DeviceVolumeMap& map, const PclVolumeEstimateParams& params,
                                  const cl::Buffer& segments, const cl::Buffer& segmentCounts, const cl::Buffer& media,
                                  double* seconds = nullptr);

// Everything on host vectors: validates (validateVolumeSegments, validateVolumeEstimateInput),
// builds the map, runs, downloads. seconds (optional) receives the device time (build + estimate).
std::vector<PclRadiance> volumeEstimateOnDevice(Device& device, const std::vector<PclPhoton>& photons,
                                                const VolumeEstimateSettings& settings, const VolumeSegments& segments,
                                                const std::vector<PclMedium>& media, double* seconds = nullptr);

}  // namespace pcl
