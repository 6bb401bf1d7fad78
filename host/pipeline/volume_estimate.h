// The volume radiance estimate (kernels/volume_estimate.cl; kernels/README.md, "volume_estimate"):
// the beam radiance estimate of Jarosz, Zwicker & Jensen 2008 along the eye pass's medium
// segments, from one volume photon map searched through a hash grid of cell size r built on the
// device each pass (pipeline/hashgrid). The twin is host/reference/volume_estimate.h.
//
//   DeviceVolumeMap map = buildVolumeMap(device, maps.volume, settings.radius);   // once per pass
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

// A volume map on the device with its hash grid (cell size r: volume_estimate.cl walks it in slabs).
struct DeviceVolumeMap {
    cl::Buffer photons;  // the map, in map order (the kernel reads power, direction and flags)
    DeviceHashGrid grid;
    float radius = 0.0f;
    double seconds = 0.0;  // device time of the grid build
};

// Uploads the photons and builds the grid. InternalError when the radius is not positive and
// finite or a photon is not a volume photon (validateVolumeEstimateInput).
DeviceVolumeMap buildVolumeMap(Device& device, const std::vector<PclPhoton>& photons, float radius);

// The launch parameters: the grid's, r and r², the kernel and its normalisation over the disc,
// the skips. InternalError when settings.radius exceeds the grid's (cell size / 2).
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
