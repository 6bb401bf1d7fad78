// Surface points the checks query at (knn.cpp, estimate.cpp, precomputed_irradiance.cpp): the closest
// hits of camera rays through random pixels, with random film, lens and time samples, so the
// points are where a render would look. Misses are skipped, at most 8 × count rays are traced.
#pragma once
#include <cstdint>
#include <random>
#include <vector>

#include "core/vec3.h"
#include "geometry/scene_geometry.h"
#include "scene/scene.h"

namespace pcl {

struct CameraSurfaceHit {
    Vec3 p;  // the hit point
    Vec3 n;  // unit geometric normal, turned to the side the camera sees
};

// A query's maxRadius2, uniform in [1/4, 1] × maxRadius² (the knn and estimate checks).
inline float randomQueryRadius2(std::mt19937_64& rng, float maxRadius) {
    std::uniform_real_distribution<float> u(0.25f, 1.0f);
    return u(rng) * maxRadius * maxRadius;
}

std::vector<CameraSurfaceHit> cameraSurfaceHits(const Scene& scene, const SceneGeometry& geometry, uint32_t count,
                                                uint64_t seed);

}  // namespace pcl
