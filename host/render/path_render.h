// The path-traced render loop, the one of `render --method path`, batch shards of method path and
// the sweep's path curve: the CPU reference path tracer (reference/path_tracer.h) over samples
// [firstSample, firstSample + samples) of every pixel. With a time budget or fixed-point sums it
// runs one sample per pixel at a time (so it can stop between samples, and each sample's film is
// rounded to fixed point on its own: batch shards then merge exactly); otherwise all samples in
// one call (each pixel's samples added in order: the same bits either way in doubles).
//
// Where the path tracer alone misses light (a delta light shining through a mirror or glass:
// reference/light_tracer.h), each sample per pixel also runs one pass of the light tracer
// (up to width × height light paths) and adds its splats: the sum is the reference. Its sums are
// kept apart and added at the end (doubles) or added as a pass of their own (fixed point), so
// both ways still give the same bits.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include "geometry/scene_geometry.h"
#include "image/film.h"
#include "image/fixed_point_film.h"
#include "scene/scene.h"

namespace pcl {

struct PathRenderSettings {
    uint64_t seed = 0;
    int threads = 0;                          // 0: all cores (never changes the bits)
    uint32_t firstSample = 0;                 // the global index of the first sample per pixel
    uint32_t samples = 64;                    // samples per pixel (with seconds > 0: at most; 0: no limit)
    double seconds = 0.0;                     // time budget: no new sample starts after it (one always runs)
    bool fixedPoint = false;                  // sum each sample's film in fixed point (batch shards)
    const std::atomic<bool>* stop = nullptr;  // set: no new sample starts (one sample at a time only)
    // Add the light tracer where the scene needs it (pathsThePathTracerMisses); false: the path
    // tracer alone (for comparisons with other path tracers, which miss the same light).
    bool lightTracing = true;
    // After each sample per pixel (done, fraction of the work or budget in [0, 1]); in one call,
    // after each tile (0, fraction).
    std::function<void(uint32_t, double)> progress;
};

struct PathRenderResult {
    Film film;                          // the sums in doubles (fixedPoint false)
    FixedPointFilm sums;                // the sums in fixed point (fixedPoint true)
    uint32_t samples = 0;               // samples per pixel rendered
    uint64_t paths = 0, discarded = 0;  // camera paths traced; NaN/Inf path values dropped (expected 0)
    double seconds = 0.0;
    bool stopped = false;  // a stop request ended it early
    // Why the light tracer ran ("" if it did not), and its light paths and splats.
    std::string lightTracing;
    uint64_t lightPaths = 0, lightSplats = 0;
};

PathRenderResult renderPathTraced(const Scene& scene, const SceneGeometry& geometry,
                                  const PathRenderSettings& settings);

}  // namespace pcl
