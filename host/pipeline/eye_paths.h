// Eye pass stage 2: eye paths (kernels/eye_paths.cl; kernels/README.md, "Eye pass: eye paths").
// Each camera ray is followed through specular chains — mirror, glass (exact Fresnel chooses
// reflection or refraction), glossy (the Phong lobe sampled: distributed ray tracing) — to the
// first hit whose diffuse part is chosen; on a mixed surface the diffuse part is chosen with
// probability P_d = lum(ρd)/(lum(ρd) + lum(ρs)), the specular part otherwise, the throughput
// divided by the choice's probability. Emitted radiance met along the chain (LE, LS+E) is summed
// with the throughput. One PclEyeHit per sample. The twin is host/reference/eye_paths.h.
//
//   PclEyeParams ep = eyeParams(cp, buffers, geometry, 8);
//   cl::Buffer hits = device.allocate<PclEyeHit>(ep.sampleCount);
//   traceEyePaths(device, deviceScene, ep, rays, hits);
#pragma once
#include <cstdint>
#include <vector>

#include "device/device.h"
#include "pipeline/device_scene.h"
#include "shared/types.h"

namespace pcl {

constexpr uint32_t kDefaultEyeDepth = 8;  // hits examined per eye path (7 specular bounces)

// Seed, sample range and samples per pixel from the camera's parameters; the scene's
// triangleCount and rayEpsilon. InternalError when maxDepth is outside 1..64.
PclEyeParams eyeParams(const PclCameraParams& camera, const SceneGeometry& geometry, const SceneBuffers& buffers,
                       uint32_t maxDepth = kDefaultEyeDepth);

// Enqueues eye_paths over params.sampleCount rays: rays (PclRay, from generateCameraRays with
// the same firstSample) in, hits (PclEyeHit[sampleCount], caller-allocated) out.
cl::Event traceEyePaths(Device& device, const DeviceScene& scene, const PclEyeParams& params, const cl::Buffer& rays,
                        cl::Buffer& hits);

}  // namespace pcl
