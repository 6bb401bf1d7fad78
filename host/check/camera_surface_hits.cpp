#include "check/camera_surface_hits.h"

#include <algorithm>
#include <random>

#include "reference/camera.h"
#include "reference/surface.h"

namespace pcl {

std::vector<CameraSurfaceHit> cameraSurfaceHits(const Scene& scene, const SceneGeometry& geometry, uint32_t count,
                                                uint64_t seed) {
    RayCamera camera(scene.camera);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<CameraSurfaceHit> hits;
    const int w = std::max(scene.camera.width, 1), h = std::max(scene.camera.height, 1);
    for (uint64_t tries = 0; hits.size() < count && tries < 8ull * count; ++tries) {
        const int x = std::min(int(u(rng) * w), w - 1), y = std::min(int(u(rng) * h), h - 1);
        CameraSample s;
        s.filmX = u(rng), s.filmY = u(rng), s.lensU = u(rng), s.lensV = u(rng), s.time = u(rng);
        const PclRay ray = camera.generateRay(x, y, s);
        PclHit hit;
        if (!geometry.intersect(ray, hit)) continue;
        const SurfacePoint sp = surfaceAt(scene, geometry, ray, hit);
        hits.push_back({sp.p, dot(sp.ng, rayDirection(ray)) > 0.0f ? -sp.ng : sp.ng});
    }
    return hits;
}

}  // namespace pcl
