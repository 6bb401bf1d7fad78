// Caustic connections (kernels/connect_caustics.cl; kernels/README.md, "connect_caustics"): every
// caustic photon of a pass joined to the camera through a lens point, as a light tracer does
// (LuxCore's hybrid back/forward path tracing), so the L S+ D E light that an eye sees directly
// comes without the caustic map's blur; the eye pass then reads the caustic map only at hits
// seen through mirrors and glass (PclEyeEstimateParams::minDepth = 1). The twin is
// host/reference/connect_caustics.h.
//
//   PclConnectParams cp = connectParams(geometry, buffers, photons.size(), passSeed, !times.empty());
//   std::vector<PclSplat> s = connectCaustics(device, scene, cp, camera, photons, times);
#pragma once
#include <cstdint>
#include <vector>

#include "device/device.h"
#include "pipeline/device_scene.h"
#include "shared/types.h"

namespace pcl {

// The distance the record's surface is searched along its normal, in multiples of the ray
// epsilon: far beyond a position's float error, short of any other surface.
constexpr float kConnectFindEpsilons = 8.0f;

// hasTimes: the records come with their shutter times (scenes that move).
PclConnectParams connectParams(const SceneGeometry& geometry, const SceneBuffers& buffers, uint32_t photonCount,
                               uint64_t passSeed, bool hasTimes = false);

// One splat per photon, in photon order (pixel PCL_NO_SPLAT: none); each connection is traced at
// times[i] (the shutter time photon i was emitted at: PhotonPassOptions::causticTimes), all at
// time 0 when params.hasTimes is 0. InternalError when the camera samples time but the records
// come without times, or times does not hold one per record.
std::vector<PclSplat> connectCaustics(Device& device, const DeviceScene& scene, const PclConnectParams& params,
                                      const PclCameraParams& camera, const std::vector<PclPhoton>& photons,
                                      const std::vector<float>& times = {});

}  // namespace pcl
