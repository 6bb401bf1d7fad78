// Eye pass stage 1: camera rays (kernels/camera.cl; kernels/README.md, "Eye pass: camera").
// A pass takes n × n stratified samples per pixel: sample s = pixel · n² + k, stratum
// (k mod n, k div n), jittered inside it; thin lens when the plan samples the lens, shutter
// time when it samples time. Random numbers: stream CAMERA, key = the pass seed, path = pixel,
// bounce = k, dimensions 0..4 (film x, film y, lens u, lens v, time) — the reference path
// tracer's Sampler layout, so a pass is reproducible on its own (batch shards split a render by pass).
// The twin is host/reference/camera_rays.h.
//
//   PclCameraParams cp = cameraParams(scene.camera, plan, eyePassSeed(seed, pass), n);
//   cl::Buffer rays = device.allocate<PclRay>(cp.sampleCount);
//   generateCameraRays(device, cp, rays);                       // rays[i] for s = firstSample + i
#pragma once
#include <cstdint>
#include <vector>

#include "device/device.h"
#include "prep/plan.h"
#include "scene/scene.h"
#include "shared/types.h"

namespace pcl {

// The seed of eye pass `pass`: seed + pass · 0x9E3779B97F4A7C15 (64-bit wrap), the photon
// pass's rule (prep/photon_allocation.h); the streams keep the two apart.
uint64_t eyePassSeed(uint64_t seed, uint32_t pass);

// Parameters for the whole pass (firstSample 0, sampleCount = width · height · n²): the camera
// frame as reference/camera.cpp builds it; lens and time sampling as the plan says (a sampler
// the plan leaves out is not run: the pinhole ray, time 0). InternalError when strata is 0 or
// above 16, or the image has no pixel.
PclCameraParams cameraParams(const Camera& camera, bool lensSampling, bool timeSampling, uint64_t passSeed,
                             uint32_t strata);
PclCameraParams cameraParams(const Camera& camera, const RenderPlan& plan, uint64_t passSeed, uint32_t strata);

// Enqueues camera_rays over params.sampleCount samples starting at params.firstSample: rays
// (PclRay[sampleCount], caller-allocated) out. Unit directions, tmin 0, tmax +inf.
cl::Event generateCameraRays(Device& device, const PclCameraParams& params, cl::Buffer& rays);

}  // namespace pcl
