// Constants the host shares by every layer. π in float is what the kernels compute with
// (PCL_PI_F, kernels/shared/sampling.h) and what the twins mirror; the double is for the
// host-only double-precision work (scene loading, projection maps).
#pragma once

namespace pcl {

constexpr double kPiD = 3.14159265358979323846;
constexpr float kPi = static_cast<float>(kPiD);

}  // namespace pcl
