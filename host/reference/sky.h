// The twins' view of the sky (scene buffers' EnvironmentBuffers): the same lookups and samples
// as the kernels, through kernels/shared/environment.h, so device and twin read the same texels.
#pragma once
#include "core/vec3.h"
#include "prep/scene_buffers.h"
#include "shared/environment.h"

namespace pcl {

inline bool skyActive(const SceneBuffers& b) { return env_active(b.sky.environment) != 0; }

// Radiance from world direction w and (pdf) the density the sky's sampling gives w.
inline Vec3 skyRadiance(const SceneBuffers& b, Vec3 w, float* pdf = nullptr) {
    float L[3];
    const float p = env_radiance(b.sky.environment, b.sky.data.data(), sampling_v3(w.x, w.y, w.z), L);
    if (pdf) *pdf = p;
    return {L[0], L[1], L[2]};
}

// A direction toward the sky from (u1, u2): its radiance L, density returned (0: none).
inline float skySample(const SceneBuffers& b, float u1, float u2, Vec3& w, Vec3& L) {
    PclV3 v;
    float l[3];
    const float p = env_sample(b.sky.environment, b.sky.data.data(), u1, u2, &v, l);
    w = Vec3(v.x, v.y, v.z);
    L = Vec3(l[0], l[1], l[2]);
    return p;
}

}  // namespace pcl
