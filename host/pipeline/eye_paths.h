// Eye pass stage 2: eye paths (kernels/eye_paths.cl; kernels/README.md, "Eye pass: eye paths").
// Each camera ray is followed through specular chains — mirror, glass (exact Fresnel chooses
// reflection or refraction), glossy (the Phong lobe sampled: distributed ray tracing) — to the
// first hit whose diffuse part is chosen; on a mixed surface the diffuse part is chosen with
// probability P_d = lum(ρd)/(lum(ρd) + lum(ρs)), the specular part otherwise, the throughput
// divided by the choice's probability. Emitted radiance met along the chain (LE, LS+E) is summed
// with the throughput, and so is the direct light at glossy hits (next-event estimation through
// the Phong lobe, MIS against the lobe's own sampling: without it a small lamp's highlight is
// found only by chance and a point light's never). In participating media the chain tracks its
// medium, attenuates by the transmittance, adds single scattering along its segments (equiangular
// next-event estimation) to the emitted sum and records the segments for the volume estimate.
// One PclEyeHit per sample. The twin is host/reference/eye_paths.h.
//
//   PclEyeParams ep = eyeParams(cp, geometry, buffers, table);
//   cl::Buffer hits = device.allocate<PclEyeHit>(ep.sampleCount);
//   traceEyePaths(device, deviceScene, deviceLights, ep, rays, hits);
#pragma once
#include <cstdint>
#include <vector>

#include "device/device.h"
#include "pipeline/device_scene.h"
#include "pipeline/direct_light.h"
#include "prep/area_light_table.h"
#include "shared/types.h"

namespace pcl {

constexpr uint32_t kDefaultEyeDepth = 8;         // hits examined per eye path (7 specular bounces)
constexpr uint32_t kDefaultVolumeSegments = 16;  // media: segment slots per eye record

// Seed, sample range and samples per pixel from the camera's parameters; the scene's
// triangleCount, rayEpsilon, light count, the area lights' total power and bounding sphere; in a
// scene with media the camera's medium and volumeSegments (0 without media). InternalError when
// maxDepth is outside 1..64 or volumeSegments is 0 in a scene with media.
PclEyeParams eyeParams(const PclCameraParams& camera, const SceneGeometry& geometry, const SceneBuffers& buffers,
                       const AreaLightTable& table, uint32_t maxDepth = kDefaultEyeDepth,
                       uint32_t volumeSegments = kDefaultVolumeSegments);

// Enqueues eye_paths over params.sampleCount rays: rays (PclRay, from generateCameraRays with
// the same firstSample) in, hits (PclEyeHit[sampleCount], caller-allocated) out. A scene
// without media only (params.volumeSegments == 0, else InternalError).
cl::Event traceEyePaths(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                        const PclEyeParams& params, const cl::Buffer& rays, cl::Buffer& hits);

// Any scene: also the medium segments, segments[c · sampleCount + i] (PclVolumeSegment[
// volumeSegments · sampleCount]) and segmentCounts[i] (uint32[sampleCount]); one-element
// placeholders when params.volumeSegments == 0 (never touched).
cl::Event traceEyePaths(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                        const PclEyeParams& params, const cl::Buffer& rays, cl::Buffer& hits, cl::Buffer& segments,
                        cl::Buffer& segmentCounts);

}  // namespace pcl
