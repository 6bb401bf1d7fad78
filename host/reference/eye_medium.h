// The eye pass in homogeneous participating media, the twin of kernels/shared/eye_medium.h
// (kernels/README.md, "Eye pass: media"), written from the README: the transmittance of a shadow
// segment through media and invisible boundaries, equiangular distance sampling (Kulla &
// Fajardo 2012) and the exit from the scene's bounding sphere. The phase function is the
// reference's henyeyGreenstein (reference/medium.h).
#pragma once
#include <cstdint>

#include "core/vec3.h"
#include "geometry/scene_geometry.h"
#include "prep/scene_buffers.h"
#include "shared/types.h"

namespace pcl {

// Per channel exp(−σt len) of medium m (1 where σt = 0, even for an infinite len).
Vec3 eyeMediumTransmittance(const PclMedium& m, float len);

// The transmittance of the shadow segment o + s dir, s ∈ (0, tmax) (dir not necessarily unit),
// starting in `medium`: closest hits in turn; an invisible boundary (PCL_MATERIAL_INTERFACE)
// switches to the medium beyond and the search goes on from p − n_f rayEpsilon, any other surface
// blocks (0); at most PCL_MAX_SEGMENTS boundaries. Without media (hasMedia false) a plain
// occlusion test: 1 or 0.
Vec3 eyeShadowTransmittance(const SceneGeometry& geometry, const SceneBuffers& buffers, bool hasMedia, int32_t medium,
                            Vec3 o, Vec3 dir, float tmax, float tau);

// Equiangular sampling of t ∈ [0, tEnd] (tEnd may be +∞) along o + t d (d unit) toward c:
// density D / ((θb − θa)(D² + (t − Δ)²)). False when the line passes through c or the interval
// is empty.
bool eyeEquiangular(Vec3 o, Vec3 d, Vec3 c, float tEnd, float u, float& t, float& pdf);

// The distance along o + t d (d unit) at which the ray leaves the sphere; 0 when it is never
// inside it ahead of o.
float eyeSphereExit(Vec3 o, Vec3 d, Vec3 centre, float radius);

}  // namespace pcl
