// Render settings, in one place: the methods, every setting with its default and the reason for
// it, parsing from the words users type (`render`'s options, a batch job's keys), validation,
// and the one serialisation of everything that changes a pixel (the EXR metadata of `render`,
// the shard settings hash and the merged image of `batch`, which therefore cannot disagree).
//
//   RenderRequest q;  q.method = "fg";  q.k = 100;         // what the user gave (0 / "": default)
//   ResolvedSettings r = resolveRenderSettings(q, plan, width, height);
//   r.settings        the settings to render with; r.choices: each default and why
//   settingsText(r.settings, plan, width, height, passes)  "method=fg;width=...;..." (exact)
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "prep/estimate_settings.h"
#include "prep/knn_structure.h"
#include "prep/plan.h"

namespace pcl {

enum class RenderMethod { FinalGather, DirectVisualisation, Progressive, PathTracing };
const char* renderMethodName(RenderMethod m);             // "fg", "direct", "progressive", "path"
RenderMethod parseRenderMethod(const std::string& name);  // InputError naming the valid ones

// Where final gathering reads the global map: Christensen's precomputed irradiance (one nearest
// lookup per gather ray) or the full k-nearest-neighbour estimate.
enum class GatherSource { Precomputed, Estimate };
const char* gatherSourceName(GatherSource g);             // "precomputed", "estimate"
GatherSource parseGatherSource(const std::string& name);  // InputError naming the valid ones

// The words of --structure and a job's "structure": "kd-tree", "hash-grid".
const char* knnStructureWord(KnnStructure s);
KnnStructure parseKnnStructure(const std::string& word);

struct PhotonRenderSettings {
    // ---- What changes pixels (every one is in settingsFields) --------------------------------
    RenderMethod method = RenderMethod::FinalGather;
    uint32_t strata = 1;                           // n: n × n stratified eye samples per pixel per pass
    uint32_t globalPhotons = 200000;               // photons emitted per pass for the global map
    uint32_t causticPhotons = 100000;              // per pass for the caustic map
    uint32_t globalK = 50;                         // photons per global-map estimate
    uint32_t causticK = 50;                        // photons per caustic estimate (fg, direct)
    uint32_t gatherRays = 64;                      // N final-gather rays per diffuse eye hit
    uint32_t lightSamples = 16;                    // M area-light samples per diffuse eye hit (M ≫ 1: the gather
                                                   // rays, N of them, would otherwise carry half the direct light)
    uint32_t eyeDepth = 0;                         // hits per eye path; 0: kDefaultEyeDepth
    float maxRadius = 0.0f;                        // kNN search radius cap; 0: 5 % of the scene's bounds diagonal
    EstimateFilter filter = EstimateFilter::Cone;  // fg/direct estimates (progressive: box)
    // The search structure of every map the pass builds (precomputed irradiance keeps its own):
    // the same photons are found either way; only the speed differs (the sweep charts both).
    KnnStructure structure = KnnStructure::KdTree;
    // Every estimate (global, caustic; fg, direct and progressive) also rejects photons whose
    // lifted segment to the query is occluded (EstimateSettings::visibility): no light through
    // walls thinner than the search radius, at the cost of one ray per photon used. fg then reads
    // the full estimate, not precomputed irradiance (its nearest-record lookup has no such test).
    bool visibility = false;
    // fg: every caustic photon joined to the camera (pipeline/connect_caustics.h), so the caustics
    // an eye sees directly come without the caustic map's blur; the map is then read only at eye
    // hits seen through mirrors and glass. Scenes whose geometry moves keep the map.
    bool causticConnections = false;
    // fg: up to M × M eye samples per pixel and pass (M > 0) for the light eye paths collect
    // before their diffuse hit (emitters seen directly or through specular and glossy chains), in
    // each row's span of pixels where a probe of 4 × 4 samples saw that light differ (an emitter's
    // edge); the span's n² eye samples then leave that light out. Lamp edges cost a path tracer
    // nothing and dominated fg's RMSE. M shrinks until the spans' samples are at most a quarter of
    // the pass's (PhotonRenderResult::emitterStrata). 0: off.
    uint32_t emitterStrata = 0;
    GatherSource gatherSource = GatherSource::Precomputed;
    // fg: a gather ray whose diffuse hit lies within closeGather × r_k of the eye hit (r_k: the
    // radius that holds globalK photons at the pass's mean density) takes the direct light
    // there by shadow rays and reads only the map's other photons: the map's estimate blurs
    // light over a disc as wide as such a ray is long (Jensen's remedy for short gather rays,
    // its direct part). 0: off.
    float closeGather = 0.0f;
    // fg: G > 0 importance-samples the gather rays from a G × G histogram of the incident flux of
    // the globalK photons nearest each eye hit (Jensen 1995; pipeline/final_gather.h), mixed with
    // the cosine density; direct light's MIS weights use the same density. 0: cosine only.
    uint32_t histogramCells = 0;
    // Progressive: the first pass's radius gives about `progressiveK0` photons per disc (from the
    // stored photons per unit scene area); r² then shrinks by (i + α)/(i + 1) each pass.
    float alpha = 2.0f / 3.0f;
    float progressiveK0 = 20.0f;
    float initialRadius = 0.0f;  // progressive r_0; 0: from progressiveK0
    // Media: the beam radiance estimate's radii. volumeK: the k of the first radius (the median
    // distance to the k-th nearest volume photon) and, with volumePhotonRadii, of each photon's
    // own radius (its k-th nearest, clamped to [r_0/4, 2 r_0]); both shrink per pass like r².
    uint32_t volumeK = 32;
    bool volumePhotonRadii = false;
    uint64_t seed = 0;

    // ---- How much, and how the run goes (no pixel depends on these) --------------------------
    uint32_t passes = 1;  // passes to run (with seconds > 0: at most this many; 0: no limit)
    // The global index of the first pass: passes [firstPass, firstPass + passes) are rendered,
    // each with its global index in the photon and eye seeds and the progressive radius, so a
    // batch shard renders exactly the passes a single run would (batch/batch_render.h).
    uint32_t firstPass = 0;
    double seconds = 0.0;                     // time budget: no new pass starts after it (at least one runs)
    uint32_t photonBatch = 0;                 // photon paths per launch; 0: the photon pass's default (the
                                              // CLI passes the memory plan's)
    bool aovs = false;                        // also keep per-part films (direct, caustic, indirect, emitted)
                                              // and the first hit's albedo and normal
    size_t chunkSamples = 0;                  // eye samples per chunk; 0: from the max allocation
    const std::atomic<bool>* stop = nullptr;  // set (e.g. by SIGINT): no new pass starts
    // After each pass: (passes done, fraction of the budget done in [0,1]).
    std::function<void(uint32_t, double)> onPass;
    bool log = false;  // one line per pass on stderr
};

// What prepareScene needs to know of the method: fg (and auto, whose pilot may pick it) leaves
// the sky's caustics to its gather rays (PlanSettings::skyCaustics); the others keep its photons.
PlanSettings planSettingsFor(const std::string& method);

// fg's closeGather when the request leaves it out (README, "Equal time at 256²").
constexpr float kDefaultCloseGather = 2.0f;

// InputError when a setting is out of its range (strata 1..16, k 1..PCL_KNN_MAX_K, gather rays
// ≥ 1, α in (0, 1)), or neither a pass count nor a time budget is given.
void validateRenderSettings(const PhotonRenderSettings& s);

// What the plan decides for `method`: which maps a pass builds.
struct RenderMaps {
    bool global = false, caustic = false, gather = false;
    // Scenes with scattering media (progressive, direct): the volume maps, read along the eye's
    // medium segments; their photons come from the global pass (and the caustic pass, if any).
    bool volume = false;
};
RenderMaps mapsFor(RenderMethod method, const RenderPlan& plan);

// What a user asks for: `render`'s options and a batch job's keys, as given. Counts of 0 and
// passes/seconds of 0 mean "the default" (resolveRenderSettings chooses it and says why).
struct RenderRequest {
    std::string method = "fg", filter = "cone", gatherSource = "precomputed", structure = "kd-tree";
    uint64_t seed = 0;
    bool visibility = false;
    uint32_t gatherImportance = 0;  // G of --gather-importance
    float closeGather = -1.0f;      // --close-gather; negative: the default
    float radius = 0.0f, alpha = 2.0f / 3.0f, maxRadius = 0.0f;
    uint32_t passes = 0;   // 0: defaultPasses (unless seconds is given)
    double seconds = 0.0;  // time budget instead of a pass count
    uint32_t globalPhotons = 0, causticPhotons = 0, k = 0, causticK = 0, lightSamples = 0, strata = 0, gatherRays = 0;
    uint32_t volumeK = 0;     // 0: the default
    std::string volumeRadii;  // "fixed", "photon"; empty: the default
    std::string caustics;     // fg: "connect", "map"; empty: the default (connect)
    int emitterStrata = -1;   // fg: the emitter samples' M (PhotonRenderSettings); -1: the default, 0: off
};

// One resolved setting, as `render` logs it: "gather rays 64  (default: <reason>)" or "(given)".
struct SettingChoice {
    std::string what;
    bool given = false;
    std::string reason;  // why the default is what it is (empty when given)
};

struct ResolvedSettings {
    PhotonRenderSettings settings;
    std::vector<SettingChoice> choices;
    std::string log() const;  // one line per choice
};

// The settings for `request` on a scene with this plan at width × height: the defaults of the
// method (photons per pass from the plan, k 50, 16 light samples, per method the eye strata and
// gather rays: 2×2 samples and a quarter of the gather rays when the plan samples a lens, a
// shutter or glossy lobes), then every value the request gives (strata not for the path tracer,
// which has none; gather rays only for fg, the one method that gathers). Passes: the request's,
// else defaultPasses unless a time budget is given; path tracing leaves passes to its caller
// (samples per pixel). InputError for unknown names.
ResolvedSettings resolveRenderSettings(const RenderRequest& request, const RenderPlan& plan, int width, int height);

// Passes of `render` with no --passes or --time: fg 10 at 256×256 scaled by pixel count (1..64),
// direct 4, progressive 32.
uint32_t defaultPasses(RenderMethod method, int width, int height);

// fg: whether an eye sample costs only its rays (camera, shadow and gather rays, lookups), so
// the defaults take many eye samples of few gather rays each: no caustic map (a k-nearest
// estimate per diffuse eye hit) and no gather importance histograms (one per eye hit).
bool fgEyeSamplesAreCheap(const PhotonRenderSettings& s, const RenderPlan& plan);
// fg: whether every eye sample pays a k-nearest caustic estimate (a caustic map, no gather
// importance): the defaults then take fewer eye samples and fewer photons per caustic estimate.
bool fgEyeSamplesReadCaustics(const PhotonRenderSettings& s, const RenderPlan& plan);

// Eye samples per chunk of the photon renderer's eye pass (the batch plan predicts the same):
// the per-sample gather buffers (32 bytes per gather ray) within a quarter of the max
// allocation, 256 .. 2^18 samples, at most a pass. (Chunks of 2^21 samples for 2 gather rays,
// sorting more gather hits together, read the lookups only ~10 % faster on cornell-box.)
size_t eyeChunkSamples(const PhotonRenderSettings& s, size_t maxAlloc, size_t passSamples);

// Every setting that changes a pixel of a `passes`-pass render at width × height, at its exact
// value (floats by their bits, %a), in a fixed order; photon counts of maps the method does not
// build are 0. The photon batch, the chunk size, the buffer cap and the shard count are left out:
// they change launch counts, not results. The path tracer's own settings are fixed (depth,
// roulette, MIS), so for it only size, passes and seed count.
struct SettingsField {
    std::string key, value;
};
std::vector<SettingsField> settingsFields(const PhotonRenderSettings& s, const RenderPlan& plan, int width, int height,
                                          uint32_t passes);
// The fields as "key=value;key=value" (batch shards, the EXR's photoncl:settings) and its hash.
std::string settingsText(const PhotonRenderSettings& s, const RenderPlan& plan, int width, int height, uint32_t passes);
uint64_t settingsHash(const std::string& text);  // FNV-1a

}  // namespace pcl
