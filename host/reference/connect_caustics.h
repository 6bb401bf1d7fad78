// CPU twin of connect_caustics (kernels/README.md, "connect_caustics"): each caustic photon
// joined to the camera, written from the light tracer's pieces (reference/camera.h's
// RayCamera::connect, surfaceAt, the host BVH) rather than from the kernel's shared headers;
// only the random numbers are shared (Philox, stream CONNECT, path = photon, block 0).
#pragma once
#include <vector>

#include "geometry/scene_geometry.h"
#include "scene/scene.h"
#include "shared/types.h"

namespace pcl {

// One splat per photon in photon order, as the kernel's; the camera's size and lens come from
// `camera` (a pinhole unless camera.lensSampling), the lens samples from params' seed; photon i
// at shutter time times[i] when params.hasTimes (else 0).
std::vector<PclSplat> referenceConnectCaustics(const Scene& scene, const SceneGeometry& geometry,
                                               const PclConnectParams& params, const PclCameraParams& camera,
                                               const std::vector<PclPhoton>& photons,
                                               const std::vector<float>& times = {});

}  // namespace pcl
