// Twin of kernels/shared/shutter_open.h: the global photon map keeps a moving surface's photons,
// and asks its queries, where the surface sits when the shutter opens (p − m τ).
#pragma once
#include "core/vec3.h"
#include "shared/types.h"

namespace pcl {

inline Vec3 shutterOpenPosition(const PclPrimInfo& info, Vec3 p, float tau) {
    return {p.x - info.mx * tau, p.y - info.my * tau, p.z - info.mz * tau};
}

}  // namespace pcl
