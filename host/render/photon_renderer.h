// The photon-mapping renderer (DESIGN.md stages 5 "gather" and 6 "resolve"; issue 6): a loop of
// passes, each one
//   photon pass (fresh photons, the pass index in the seed) → the maps the plan needs →
//   camera → eye paths (specular chains to the first diffuse hit) → at that hit:
//     fg:          direct light by shadow rays + caustic map + final gathering into the global map
//     direct:      the global map read at the hit (preview; its photons carry direct light too)
//     progressive: direct light + caustic map + the global map's indirect photons (those after a
//                  diffuse bounce), both read with a fixed radius that shrinks from pass to pass,
//                  r²_{i+1} = r²_i (i + α)/(i + 1) (Knaus & Zwicker 2011, probabilistic PPM)
//   → every sample's radiance (emitted + the parts above) added to the film.
// Eye samples are processed in chunks so the gather buffers stay within the device's max
// allocation. The film holds the average over the passes done; a stop request (Ctrl-C) is
// honoured between passes, so the film always holds whole passes.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "image/film.h"
#include "image/fixed_point_film.h"
#include "pipeline/estimate.h"
#include "pipeline/plan.h"
#include "pipeline/scene_buffers.h"
#include "scene/scene.h"

namespace pcl {

enum class RenderMethod { FinalGather, DirectVisualisation, Progressive, PathTracing };
const char* renderMethodName(RenderMethod m);           // "fg", "direct", "progressive", "path"
RenderMethod parseRenderMethod(const std::string& name);  // InputError naming the valid ones

// Where final gathering reads the global map: Christensen's precomputed irradiance (one nearest
// lookup per gather ray) or the full k-nearest-neighbour estimate.
enum class GatherSource { Precomputed, Estimate };

struct PhotonRenderSettings {
    RenderMethod method = RenderMethod::FinalGather;
    uint32_t passes = 1;              // passes to run (with seconds > 0: at most this many; 0: no limit)
    // The global index of the first pass: passes [firstPass, firstPass + passes) are rendered,
    // each with its global index in the photon and eye seeds and the progressive radius, so a
    // batch shard renders exactly the passes a single run would (batch/batch_render.h).
    uint32_t firstPass = 0;
    double seconds = 0.0;             // time budget: no new pass starts after it (at least one runs)
    uint32_t strata = 1;              // n: n × n stratified eye samples per pixel per pass
    uint32_t globalPhotons = 200000;  // photons emitted per pass for the global map
    uint32_t causticPhotons = 100000; // per pass for the caustic map
    uint32_t globalK = 50;            // photons per global-map estimate
    uint32_t causticK = 50;           // photons per caustic estimate (fg, direct)
    uint32_t gatherRays = 64;         // N final-gather rays per diffuse eye hit
    uint32_t lightSamples = 8;        // M area-light samples per diffuse eye hit (M ≫ 1: the gather
                                      // rays, N of them, would otherwise carry half the direct light)
    uint32_t eyeDepth = 0;            // hits per eye path; 0: kDefaultEyeDepth
    float maxRadius = 0.0f;           // kNN search radius cap; 0: 5 % of the scene's bounds diagonal
    EstimateFilter filter = EstimateFilter::Cone;     // fg/direct estimates (progressive: box)
    // The search structure of every map the pass builds (precomputed irradiance keeps its own):
    // the same photons are found either way; only the speed differs (the sweep charts both).
    KnnStructure structure = KnnStructure::KdTree;
    // Every estimate (global, caustic; fg, direct and progressive) also rejects photons whose
    // lifted segment to the query is occluded (EstimateSettings::visibility): no light through
    // walls thinner than the search radius, at the cost of one ray per photon used. fg then reads
    // the full estimate, not precomputed irradiance (its nearest-record lookup has no such test).
    bool visibility = false;
    GatherSource gatherSource = GatherSource::Precomputed;
    // fg: G > 0 importance-samples the gather rays from a G × G histogram of the incident flux of
    // the globalK photons nearest each eye hit (Jensen 1995; pipeline/final_gather.h), mixed with
    // the cosine density; direct light's MIS weights use the same density. 0: cosine only.
    uint32_t histogramCells = 0;
    // Progressive: the first pass's radius gives about `progressiveK0` photons per disc (from the
    // stored photons per unit scene area); r² then shrinks by (i + α)/(i + 1) each pass.
    float alpha = 2.0f / 3.0f;
    float progressiveK0 = 20.0f;
    float initialRadius = 0.0f;       // progressive r_0; 0: from progressiveK0
    uint64_t seed = 0;
    uint32_t photonBatch = 0;         // photon paths per launch; 0: the photon pass's default (the
                                      // CLI passes the memory plan's)
    bool aovs = false;                // also keep per-part films (direct, caustic, indirect, emitted)
                                      // and the first hit's albedo and normal
    size_t chunkSamples = 0;          // eye samples per chunk; 0: from the max allocation
    const std::atomic<bool>* stop = nullptr;  // set (e.g. by SIGINT): no new pass starts
    // After each pass: (passes done, fraction of the budget done in [0,1]).
    std::function<void(uint32_t, double)> onPass;
    bool log = false;                 // one line per pass on stderr
};

// Wall seconds per stage summed over the passes (each stage waits for its launches).
struct StageTimes {
    double photons = 0, maps = 0, camera = 0, eyePaths = 0, direct = 0, caustic = 0, indirect = 0,
           accumulate = 0, total = 0;
    std::string table() const;  // one "stage  seconds  share" line per stage
};

// Per-part films (RenderSettings::aovs): each part's radiance per sample, averaged like the film.
struct RenderAovs {
    Film direct, caustic, indirect, emitted, albedo, normal;
};

struct PhotonRenderResult {
    // Each pass is rendered into a Film of doubles and its per-pixel sums are rounded once to
    // 128-bit fixed point and added (image/fixed_point_film.h): integer sums do not depend on how
    // passes are grouped, so the same passes rendered in one run or as batch shards and merged
    // give the same bits. `film` is `sums` as doubles (for callers that merge or resolve films).
    FixedPointFilm sums;
    Film film;
    RenderAovs aovs;                  // empty films unless settings.aovs
    StageTimes times;
    uint32_t passes = 0;              // passes done (the film holds exactly these)
    bool stopped = false;             // a stop request ended the render early
    uint64_t globalEmitted = 0, causticEmitted = 0, globalStored = 0, causticStored = 0;  // over all passes
    uint64_t samples = 0;             // eye samples traced
    uint64_t nonFiniteSamples = 0;    // samples whose radiance was NaN/Inf: dropped (expected 0)
    float firstRadius = 0, lastRadius = 0;  // progressive: r_0 and the last pass's radius (global map)
    size_t chunkSamples = 0;
    std::string summary;              // the settings as used, one line (for logs and metadata)
};

// What the plan decides for `method`: which maps a pass builds.
struct RenderMaps {
    bool global = false, caustic = false, gather = false;
};
RenderMaps mapsFor(RenderMethod method, const RenderPlan& plan);

// The settings `render` uses for s.method when given no options (its log says why; `sweep`
// starts from them too): photons per pass from the plan, k 50, 16 light samples, and per method
// the eye strata and gather rays (2×2 samples and a quarter of the gather rays when the plan
// samples a lens, a shutter or glossy lobes). Passes are left alone: defaultPasses.
void applyRenderDefaults(PhotonRenderSettings& s, const RenderPlan& plan);
// The counts a user sets (`render`'s options, a batch job's keys); 0: keep the default.
struct RenderOverrides {
    uint32_t globalPhotons = 0, causticPhotons = 0, k = 0, causticK = 0, lightSamples = 0, strata = 0,
             gatherRays = 0;
};
// applyRenderDefaults, then every override given (strata not for the path tracer, which has
// none; gather rays only for fg, the one method that gathers), so `render` and `batch` resolve
// a job's settings alike.
void applyRenderDefaults(PhotonRenderSettings& s, const RenderPlan& plan, const RenderOverrides& given);
// Passes of `render` with no --passes or --time: fg 10 at 256×256 scaled by pixel count (1..64),
// direct 4, progressive 32.
uint32_t defaultPasses(RenderMethod method, int width, int height);

// Total area of the scene's surfaces (triangles and spheres), for photon densities.
double sceneSurfaceArea(const Scene& scene);

// The progressive radius schedule: r²_i for pass i from r²_0 (Knaus & Zwicker 2011, eq. 13).
double progressiveRadius2(double r0Squared, double alpha, uint32_t pass);

// Renders scene.camera's image with the photon-mapping method settings.method (not
// PathTracing: that is reference/path_tracer.h). `buffers` must hold the projection maps.
PhotonRenderResult renderPhotonMapped(Device& device, const Scene& scene, const SceneGeometry& geometry,
                                      const SceneBuffers& buffers, const RenderPlan& plan,
                                      const PhotonRenderSettings& settings);

}  // namespace pcl
