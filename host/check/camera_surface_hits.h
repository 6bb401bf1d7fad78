// Surface points the checks query at (check_knn, check_estimate, check_irradiance): the closest
// hits of camera rays through random pixels, with random film, lens and time samples, so the
// points are where a render would look. Misses are skipped, at most 8 × count rays are traced.
#pragma once
#include <cstdint>
#include <vector>

#include "core/vec3.h"
#include "geometry/scene_geometry.h"
#include "scene/scene.h"

namespace pcl {

struct CameraSurfaceHit {
    Vec3 p;  // the hit point
    Vec3 n;  // unit geometric normal, turned to the side the camera sees
};

std::vector<CameraSurfaceHit> cameraSurfaceHits(const Scene& scene, const SceneGeometry& geometry, uint32_t count,
                                                uint64_t seed);

}  // namespace pcl
