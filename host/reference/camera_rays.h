// CPU twin of the camera stage (kernels/README.md, "Eye pass: camera"): the reference camera
// (reference/camera.h) fed with the stratified film point, the lens point and the time of
// sample s from the reference Sampler (stream CAMERA, path = pixel, bounce = k).
#pragma once
#include <vector>

#include "scene/scene.h"
#include "shared/types.h"

namespace pcl {

// Rays of samples [params.firstSample, + params.sampleCount).
std::vector<PclRay> referenceCameraRays(const Camera& camera, const PclCameraParams& params);

}  // namespace pcl
