// Per-pixel statistics of the reference path tracer for the accuracy tests that compare pixels
// with closed forms by a Z-test, and the knobs that let a run vary seed and samples
// (PHOTONCL_TEST_SEED, PHOTONCL_TEST_SPP_SCALE) to show a test is not tuned to one seed.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "geometry/scene_geometry.h"
#include "reference/camera.h"
#include "reference/path_tracer.h"
#include "reference/sampler.h"
#include "scene/scene.h"

namespace pcl {

// To tell noise from bias: PHOTONCL_TEST_SEED=3 accuracy_tests --gtest_filter='Medium*' moves every
// seed a test uses by 3000 (they stay distinct from each other).
inline uint64_t testSeed(uint64_t seed) {
    if (const char* s = std::getenv("PHOTONCL_TEST_SEED")) seed += std::strtoull(s, nullptr, 10) * 1000;
    return seed;
}
inline int testSpp(int spp) {
    if (const char* scale = std::getenv("PHOTONCL_TEST_SPP_SCALE")) spp *= std::max(1, std::atoi(scale));
    return spp;
}

// Per-pixel mean and standard error of the path tracer's estimate, sample by sample as
// PathTracer::render draws them.
struct PixelStats {
    std::vector<Vec3> mean, stdError;
};
inline PixelStats renderWithErrors(const Scene& scene, const PathTracerSettings& settings) {
    SceneGeometry geometry = SceneGeometry::build(scene);
    PathTracer tracer(scene, geometry, settings);
    RayCamera camera(scene.camera);
    const int w = scene.camera.width, h = scene.camera.height, n = settings.samplesPerPixel;
    PixelStats out;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
            for (int i = 0; i < n; ++i) {
                Sampler sampler(settings.seed, uint32_t(y * w + x), uint32_t(i));
                const Vec3 L = tracer.Li(camera.generateRay(x, y, PathTracer::cameraSample(sampler)), sampler);
                for (int c = 0; c < 3; ++c) {
                    sum[c] += L[c];
                    sum2[c] += double(L[c]) * L[c];
                }
            }
            Vec3 mean, se;
            for (int c = 0; c < 3; ++c) {
                const double m = sum[c] / n;
                mean[c] = float(m);
                se[c] = float(std::sqrt(std::max(0.0, sum2[c] / n - m * m) / (n - 1)));
            }
            out.mean.push_back(mean);
            out.stdError.push_back(se);
        }
    return out;
}

// Whether pixel (x, y)'s whole footprint sees the sphere (centre, radius): 1 when all n × n camera
// rays through film positions 0, 1/(n−1) … 1 hit it, 0 when none do, −1 on its edge (tests skip
// those).
inline int sphereCoverage(const Camera& cam, int x, int y, int n, Vec3 centre, float radius) {
    const RayCamera camera(cam);
    int hits = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            CameraSample cs;
            cs.filmX = float(i) / float(n - 1);
            cs.filmY = float(j) / float(n - 1);
            const PclRay r = camera.generateRay(x, y, cs);
            const Vec3 o(r.ox, r.oy, r.oz), d = normalize(Vec3(r.dx, r.dy, r.dz));
            const Vec3 oc = o - centre;
            const float b = dot(oc, d), c = dot(oc, oc) - radius * radius;
            hits += b * b - c > 0.0f && -b > 0.0f;
        }
    return hits == n * n ? 1 : (hits == 0 ? 0 : -1);
}

// The same for the scene's first sphere.
inline int sphereCoverage(const Scene& scene, int x, int y, int n) {
    return sphereCoverage(scene.camera, x, y, n, scene.spheres[0].centre, scene.spheres[0].radius);
}

}  // namespace pcl
