// The reference path tracer (`photoncl render --method path`, `--device ref`): unbiased
// unidirectional path tracing with next-event estimation and multiple importance sampling
// (Veach 1997, power heuristic) between light sampling and BSDF sampling for emitting surfaces;
// delta lights (point, spot, directional) by light sampling only; Russian roulette on the path
// throughput. Participating media (homogeneous, reference/medium.h): free-flight sampling on
// every segment inside a medium, next-event estimation at scattering events with shadow rays
// that carry transmittance through invisible medium boundaries, and MIS between light and
// Henyey–Greenstein phase sampling for area lights there as at surfaces; the medium a path is in
// follows the surfaces it crosses (prep/medium_boundaries.h). Deterministic: pixel (x, y), sample s always uses the same random numbers
// (sampler.h), whatever the thread count, and each pixel's samples are added in order.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/scene_geometry.h"
#include "image/film.h"
#include "prep/medium_boundaries.h"
#include "reference/bsdf.h"
#include "reference/camera.h"
#include "reference/light_sampling.h"
#include "reference/sampler.h"
#include "scene/scene.h"

namespace pcl {

struct PathTracerSettings {
    int samplesPerPixel = 16;
    int firstSample = 0;  // render samples [firstSample, firstSample + samplesPerPixel):
                          // shards of one render merge into exactly the single-run film
    // Scattering events after the camera ray (surface bounces and scattering in media; crossing
    // an invisible medium boundary is none): 1 = direct light and single scattering only.
    // Russian roulette ends paths long before 64.
    int maxDepth = 64;
    int rouletteDepth = 3;  // Russian roulette from this bounce on
    uint64_t seed = 0;
    int threads = 0;  // 0: std::thread::hardware_concurrency()
    // false: BSDF sampling only, no light sampling and no MIS; delta lights then contribute
    // nothing. An independent estimator of the same image, for tests of the MIS weights.
    bool lightSampling = true;
    // In media, single scattering from point and spot lights also by equiangular sampling (Kulla &
    // Fajardo 2012) on every segment, MIS-combined (power heuristic) with the light sample at
    // free-flight events: light shafts converge far faster. false: free-flight events alone.
    bool equiangular = true;
    // Called with the fraction done (0..1] after each tile, from worker threads but never two at
    // once. Keep it cheap: it runs under the tiles' lock.
    std::function<void(double)> progress;
};

struct PathTracerStats {
    double seconds = 0.0;           // wall time of render()
    uint64_t samples = 0;           // camera paths traced
    uint64_t discardedSamples = 0;  // NaN/Inf path values dropped (expected 0)
    double samplesPerSecond() const { return seconds > 0.0 ? static_cast<double>(samples) / seconds : 0.0; }
};

class PathTracer {
public:
    PathTracer(const Scene& scene, const SceneGeometry& geometry, PathTracerSettings settings);

    // Renders the scene camera's full image.
    Film render(PathTracerStats* stats = nullptr) const;

    // Radiance arriving along a camera ray (one path sample), numbers from `sampler`.
    Vec3 Li(PclRay ray, Sampler& sampler) const;

    // The film, lens and time numbers of a path (sampler.h, CameraDims): what render() gives the
    // camera before Li, for callers that trace pixels themselves.
    static CameraSample cameraSample(Sampler& sampler);

    // Transmittance along the straight segment from `from` to `to` at shutter time `time`,
    // starting in the medium at `from`: the product of exp(−σt d) over the media it passes,
    // through invisible medium boundaries; 0 if any other surface is in between.
    Vec3 transmittance(Vec3 from, Vec3 to, float time) const;

private:
    Vec3 sampleDirect(const SurfacePoint& s, const MixedBsdf& bsdf, Vec3 wo, int32_t medium, Sampler& sampler,
                      uint32_t vertex) const;
    // A straight stretch of a path inside one medium: unit direction, length (may be infinite)
    // and the throughput the free flight along it was sampled for.
    struct MediumSegment {
        Vec3 origin, dir;
        float length;
        Vec3 beta;
    };
    Vec3 sampleDirectInMedium(Vec3 p, Vec3 wo, float time, int32_t medium, const MediumSegment& segment, float t,
                              Sampler& sampler, uint32_t vertex) const;
    // Single scattering along the segment from one positional light, at an equiangular distance.
    Vec3 sampleEquiangular(const MediumSegment& segment, float time, int32_t medium, Sampler& sampler,
                           uint32_t vertex) const;
    // The density with which the equiangular strategy picks emitter e (0: not positional).
    float equiangularChoice(size_t emitter) const;
    // What reaches the end of a shadow ray that starts in `medium`: 0 when a surface blocks it,
    // else the transmittance of the media it passes (1 in a scene without media).
    Vec3 shadowTransmittance(PclRay shadow, int32_t medium) const;

    const Scene& scene_;
    const SceneGeometry& geometry_;
    PathTracerSettings settings_;
    RayCamera camera_;
    LightSampler lights_;
    bool hasMedia_ = false;
    MediumBoundaries boundaries_;  // filled only when the scene has media
    // Equiangular sampling's lights: the positional emitters and their cumulative choice
    // probabilities (∝ the light sampler's), empty without media or positional lights.
    std::vector<size_t> positional_;
    std::vector<float> positionalCdf_;
};

}  // namespace pcl
