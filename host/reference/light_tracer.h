// The reference light tracer (particle tracing with connections to the camera; Veach 1997
// §10.2, pbrt-v4's LightPath estimator s = k, t = 1): the paths the path tracer cannot find.
//
// The path tracer (path_tracer.h) reaches a delta light (point, spot, directional) only by next-event
// estimation, from a non-delta vertex: a path whose vertex next to a delta light is a mirror or
// glass (L S ... E, a point light's caustic) has zero chance there. The light tracer traces
// from the delta lights and, in ThroughSpecular mode, keeps exactly those paths: the first
// surface hit must scatter through a delta lobe; every later non-delta vertex is connected to
// the camera (a shadow ray to the pinhole or a sampled point on the thin lens). The two
// estimators count disjoint sets of paths — the vertex next to the light scatters through a
// non-delta lobe (path tracer) or a delta one (light tracer) — so their sum needs no MIS:
//   L D ... E            path tracer (next-event estimation)
//   L S ... D E          light tracer, connected at the last vertex
//   area light ... E     path tracer (both techniques, MIS)
// Found by neither, and missing from the sum: L S ... S E, light from a delta light through a
// specular surface that the camera sees only through a specular surface again (the caustic
// under a glass ball seen in a mirror ball, the point light's reflections seen through glass).
// Those pixels are the ones whose camera ray first hits a delta lobe; no estimator that connects
// non-delta vertices (bidirectional path tracing included) finds L S D S E either. L S* E, the
// delta light itself seen in a mirror, is an infinitely thin image that no method here renders.
//
// Emission aims at the specular objects (Jensen's projection map, exact): in ThroughSpecular
// mode a path counts only if its first hit scatters through a delta lobe, which lies inside the
// bounding sphere of a mirror or dielectric primitive, so a point or spot light samples
// directions in the cones of those spheres and a directional light points on their shadows
// (discs) — the density is the mixture's, counting every cone or disc that holds the sample.
// A light inside a bounding sphere emits uniformly. All mode always emits uniformly.
//
// Units: pass s traces N light paths, N = width × height times the fraction of the lights'
// power aimed at the targets (All: width × height), so a pass finds about as many specular
// first bounces as width × height uniform paths would. Each connection adds β f G We / N to its
// pixel (β the path's flux weight), an unbiased estimate of the pixel's average radiance from
// those paths, splatted into the film's sums (Film::splat) with weight 1 per pass, the weight a
// path-traced sample gives a pixel. Refraction carries flux unscaled (no η², importance
// transport); shading normals get pbrt-v4's adjoint correction |ω_in·ns| |ω_out·ng| / (|ω_in·ng| |ω_out·ns|).
//
// Deterministic: light path i of pass s always uses the same random numbers (Philox stream
// LIGHT_PATH, path i, bounce word s), and splats are added in path order, whatever the thread count.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "geometry/scene_geometry.h"
#include "image/film.h"
#include "reference/camera.h"
#include "scene/scene.h"

namespace pcl {

enum class LightTracerPaths {
    ThroughSpecular,  // the complement of the path tracer: first bounce through a delta lobe
    All,              // every path from the delta lights (a check against the path tracer)
};

struct LightTracerSettings {
    uint64_t seed = 0;
    int threads = 0;         // 0: std::thread::hardware_concurrency(); never changes the bits
    uint32_t firstPass = 0;  // passes [firstPass, firstPass + passes): pass s pairs with
    uint32_t passes = 1;     // path-traced sample s of every pixel
    int maxDepth = 64;       // bounces after the light; Russian roulette ends paths long before
    int rouletteDepth = 3;   // Russian roulette from this bounce on
    LightTracerPaths paths = LightTracerPaths::ThroughSpecular;
    bool aim = true;  // false: ThroughSpecular emits uniformly too (a check of the aimed densities)
};

struct LightTracerStats {
    double seconds = 0.0;
    uint64_t paths = 0;      // light paths traced
    uint64_t splats = 0;     // connections that reached the film
    uint64_t discarded = 0;  // NaN/Inf splats dropped (expected 0)
};

class LightTracer {
public:
    LightTracer(const Scene& scene, const SceneGeometry& geometry, LightTracerSettings settings);

    // Adds each pass's estimate to `film`'s sums (Film::splat, no weight); film has the
    // camera's size (InputError otherwise).
    void render(Film& film, LightTracerStats* stats = nullptr) const;

    // Light paths per pass (0: no delta light, nothing to trace).
    uint32_t pathsPerPass() const { return pathsPerPass_; }

private:
    struct Splat {
        uint32_t pixel;
        Vec3 value;
    };
    // A bounding sphere of a mirror or dielectric primitive (over the shutter interval).
    struct Target {
        Vec3 centre;
        float radius;
    };
    // How one delta light emits: uniformly, or aimed at the targets (cones or discs).
    struct Emission {
        uint32_t light = 0;  // index into scene.lights
        bool aimed = false;
        std::vector<Vec3> axis;     // point, spot: unit direction to each target
        std::vector<float> cosMax;  //   and its cone's half-angle cosine
        std::vector<Vec3> disc;     // directional: each target's disc centre on the start plane
        std::vector<float> radius;  //   and its radius
        std::vector<double> cdf;    // target choice, by solid angle or area
        double measure = 0.0;       // total solid angle or area of the cones or discs
    };
    void tracePath(uint32_t pass, uint32_t path, std::vector<Splat>& splats, uint64_t& discarded) const;
    Emission emissionOf(uint32_t light, double& aimedFraction) const;

    const Scene& scene_;
    const SceneGeometry& geometry_;
    LightTracerSettings settings_;
    RayCamera camera_;
    std::vector<Target> targets_;
    std::vector<Emission> lights_;  // the delta lights
    std::vector<double> cdf_;       // chosen by the power they aim at the targets
    std::vector<float> probability_;
    uint32_t pathsPerPass_ = 0;
    Vec3 sceneCentre_;
    float sceneRadius_ = 1.0f;  // directional lights: the disc their parallel rays start from
};

// Why the path tracer alone misses light in `scene`: "" when it misses none, else a sentence
// naming a delta light and a material with a delta lobe (mirror or dielectric).
std::string pathsThePathTracerMisses(const Scene& scene);

// Per pixel of scene.camera (row-major): 1 where none of n × n camera rays through the pixel
// (pinhole, time 0) first hits a surface with a delta lobe (mirror, glass), 0 where one does:
// the pixels that L S ... S E light can reach, which the path and light tracers' references
// lack (compare --skip-specular-pixels measures without them).
std::vector<uint8_t> pixelsSeeingNoDeltaSurfaceFirst(const Scene& scene, const SceneGeometry& geometry, int n = 4);

}  // namespace pcl
