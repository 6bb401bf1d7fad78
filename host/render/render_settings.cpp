#include "render/render_settings.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/error.h"
#include "core/hash.h"
#include "image/fixed_point_film.h"
#include "pipeline/eye_paths.h"

namespace pcl {
namespace {

// %a: the exact bits of a float, so two settings texts are equal exactly when the values are.
std::string exact(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%a", v);
    return buf;
}

}  // namespace

bool fgEyeSamplesAreCheap(const PhotonRenderSettings& s, const RenderPlan& plan) {
    return (!plan.causticMap || s.causticConnections) && s.histogramCells == 0;
}

bool fgEyeSamplesReadCaustics(const PhotonRenderSettings& s, const RenderPlan& plan) {
    return plan.causticMap && !s.causticConnections && s.histogramCells == 0;
}

namespace {

// The method's defaults (what `render` uses with no options), without the user's values.
void applyMethodDefaults(PhotonRenderSettings& s, const RenderPlan& plan) {
    s.globalPhotons = plan.globalPhotons ? plan.globalPhotons : 200000;
    s.causticPhotons = plan.causticPhotons ? plan.causticPhotons : 100000;
    s.globalK = 50;
    s.causticK = 50;
    s.lightSamples = 16;
    const bool distributed = plan.lensSampling || plan.timeSampling || plan.glossySampling;
    switch (s.method) {
        case RenderMethod::FinalGather:
            if (fgEyeSamplesAreCheap(s, plan)) {
                // Many eye samples, few gather rays and shadow rays each: at equal time the error
                // sat in the pixels eye samples decide (lamp edges, corners, shadows: one sample
                // per pass left them aliased), while 2 gather rays per sample, 72 per pixel and
                // pass, keep the indirect noise of 64. Measured at 256² against path tracing
                // (README, "Equal time at 256²"; scripts/equal_time.py): cornell-box at 10, 30 and
                // 60 s, RMSE 1.5-1.6x and relMSE 2.5-4x below the path tracer's, where 1 x 64
                // gather rays lost by RMSE 3.4-4.4x.
                s.strata = 6;
                s.gatherRays = 2;
                s.lightSamples = 2;
                // With caustic connections the caustic map is read only through mirrors and glass,
                // 20 photons an estimate as below (the equal-time runs of the connections used it).
                if (s.causticConnections) s.causticK = 20;
            } else if (fgEyeSamplesReadCaustics(s, plan)) {
                // A k-nearest caustic estimate per eye sample: fewer eye samples (4x4) of 4 gather
                // rays and 2 shadow rays, and 20 caustic photons per estimate instead of 50 (16
                // samples per pixel and pass, each pass with fresh photons, average the noise; the
                // search costs less and blurs less). cornell-spheres at 256², 10/30 s: RMSE 0.046 /
                // 0.029 and relMSE 0.0046 / 0.0031 against the path tracer's 0.085 / 0.035 and
                // 0.072 / 0.014 (1 x 64 gather rays: RMSE 0.20 / 0.10).
                s.strata = 4;
                s.gatherRays = 4;
                s.lightSamples = 2;
                s.causticK = 20;
            } else {
                // A k-nearest search per eye sample for the gather importance histograms makes
                // eye samples dear: few of them, many gather rays.
                // Lens, shutter and glossy lobes are sampled by the eye samples: scenes that need
                // them get 2×2 per pass and a quarter of the gather rays.
                s.strata = distributed ? 2 : 1;
                s.gatherRays = distributed ? 16 : 64;
            }
            break;
        case RenderMethod::DirectVisualisation:
            s.gatherRays = 1;
            s.strata = 2;
            break;
        case RenderMethod::Progressive:
            // 2×2 eye samples per pass on surfaces: at 256² and equal time (scripts/equal_time.py,
            // 10 and 30 s) RMSE 1.4-1.9x lower than one sample per pass on cornell-box and
            // cornell-spheres (lamp edges, shadows, the caustic), relMSE within 15 %. In media
            // every eye sample pays a beam estimate: one per pass (2×2 took fewer passes there,
            // a larger last radius, and was no better by relMSE on cornell-fog).
            s.gatherRays = 1;
            s.strata = plan.volumeMap ? 1 : 2;
            break;
        case RenderMethod::PathTracing: break;
    }
}

}  // namespace

const char* renderMethodName(RenderMethod m) {
    switch (m) {
        case RenderMethod::FinalGather: return "fg";
        case RenderMethod::DirectVisualisation: return "direct";
        case RenderMethod::Progressive: return "progressive";
        case RenderMethod::PathTracing: return "path";
    }
    return "?";
}

RenderMethod parseRenderMethod(const std::string& name) {
    for (RenderMethod m : {RenderMethod::FinalGather, RenderMethod::DirectVisualisation, RenderMethod::Progressive,
                           RenderMethod::PathTracing})
        if (name == renderMethodName(m)) return m;
    throw InputError("render method '" + name + "': expected fg, direct, progressive or path");
}

const char* gatherSourceName(GatherSource g) { return g == GatherSource::Estimate ? "estimate" : "precomputed"; }

GatherSource parseGatherSource(const std::string& name) {
    for (GatherSource g : {GatherSource::Precomputed, GatherSource::Estimate})
        if (name == gatherSourceName(g)) return g;
    throw InputError("gather source '" + name + "': expected precomputed or estimate");
}

const char* knnStructureWord(KnnStructure s) { return s == KnnStructure::HashGrid ? "hash-grid" : "kd-tree"; }

KnnStructure parseKnnStructure(const std::string& word) {
    for (KnnStructure s : {KnnStructure::KdTree, KnnStructure::HashGrid})
        if (word == knnStructureWord(s)) return s;
    throw InputError("search structure '" + word + "': expected kd-tree or hash-grid");
}

void validateRenderSettings(const PhotonRenderSettings& s) {
    if (s.strata < 1 || s.strata > 16)
        throw InputError("render: strata must be 1..16, got " + std::to_string(s.strata));
    if (s.emitterStrata > 16)
        throw InputError("render: emitter strata must be 0..16, got " + std::to_string(s.emitterStrata));
    if (s.gatherRays < 1) throw InputError("render: gather rays must be at least 1");
    if (s.globalK < 1 || s.globalK > PCL_KNN_MAX_K || s.causticK < 1 || s.causticK > PCL_KNN_MAX_K)
        throw InputError("render: k must be 1.." + std::to_string(PCL_KNN_MAX_K));
    if (!(s.alpha > 0.0f && s.alpha < 1.0f)) throw InputError("render: alpha must be in (0, 1)");
    if (s.histogramCells > PCL_GATHER_MAX_CELLS)
        throw InputError("render: gather importance cells must be 0..16, got " + std::to_string(s.histogramCells));
    if (!(s.maxRadius >= 0.0f && std::isfinite(s.maxRadius)))
        throw InputError("render: max radius must be finite and ≥ 0 (0: the default), got " +
                         std::to_string(s.maxRadius));
    if (!(s.initialRadius >= 0.0f && std::isfinite(s.initialRadius)))
        throw InputError("render: radius must be finite and ≥ 0 (0: the default), got " +
                         std::to_string(s.initialRadius));
    if (s.passes == 0 && !(s.seconds > 0.0)) throw InputError("render: give a pass count or a time budget");
}

RenderMaps mapsFor(RenderMethod method, const RenderPlan& plan) {
    RenderMaps maps;
    switch (method) {
        case RenderMethod::FinalGather:
            maps.global = plan.globalMap && plan.finalGather;
            maps.gather = maps.global;
            maps.caustic = plan.causticMap;
            break;
        case RenderMethod::DirectVisualisation:
            maps.global = true;  // the preview reads every kind of light from the global map
            maps.volume = plan.volumeMap;
            break;
        case RenderMethod::Progressive:
            maps.global = plan.globalMap || plan.volumeMap;
            maps.caustic = plan.causticMap;
            maps.volume = plan.volumeMap;
            break;
        case RenderMethod::PathTracing: break;
    }
    return maps;
}

uint32_t defaultPasses(RenderMethod method, int width, int height) {
    const double megapixels = double(width) * height / 1e6;
    switch (method) {
        // One 256² pass with 64 gather rays takes ~2-6 s under PoCL on 2 cores.
        case RenderMethod::FinalGather:
            return uint32_t(std::clamp(int(10 * 0.065536 / std::max(megapixels, 1e-6) + 0.5), 1, 64));
        case RenderMethod::DirectVisualisation: return 4;  // a preview: seconds
        case RenderMethod::Progressive: return 32;
        case RenderMethod::PathTracing: break;
    }
    return 0;
}

std::string ResolvedSettings::log() const {
    std::string out;
    for (const SettingChoice& c : choices)
        out += "  " + c.what + (c.given ? std::string("  (given)") : "  (default: " + c.reason + ")") + "\n";
    return out;
}

// Media (scripts/media_accuracy.py, 3 seeds of default renders each, 2026-12-02): per-photon radii
// gave the same error (relMSE 0.00142-0.00144 vs 0.00144-0.00145 on cornell-fog, 0.0038-0.0040 vs
// 0.0039-0.0041 on hazy-room, both at the references' own noise) at 1.2-2.9x the time (the kNN
// search, and a reach of 2 r0 for the search).
constexpr const char* kVolumeRadiiReason =
    "one radius per pass: per-photon radii gave the same error on the media scenes at more time";
constexpr const char* kVolumeKReason = "about 32 volume photons in the first radius";

// The defaults below were measured on the 2-core PoCL machine (README, "Commands"):
// cornell-spheres at 256×256 renders in under a minute with them.
PlanSettings planSettingsFor(const std::string& method) {
    PlanSettings p;
    p.skyCaustics = method != "fg" && method != "auto";
    return p;
}

ResolvedSettings resolveRenderSettings(const RenderRequest& q, const RenderPlan& plan, int width, int height) {
    ResolvedSettings r;
    PhotonRenderSettings& s = r.settings;
    s.method = parseRenderMethod(q.method);
    s.seed = q.seed;
    s.filter = parseEstimateFilter(q.filter);
    s.visibility = q.visibility;
    s.structure = parseKnnStructure(q.structure);
    s.gatherSource = parseGatherSource(q.gatherSource);
    s.alpha = q.alpha;
    s.histogramCells = q.gatherImportance;
    s.initialRadius = q.radius;
    s.maxRadius = q.maxRadius;
    s.seconds = q.seconds;
    const bool fgCaustics = s.method == RenderMethod::FinalGather && plan.causticMap;
    if (!q.caustics.empty() && q.caustics != "connect" && q.caustics != "map")
        throw InputError("render: caustics \"" + q.caustics + "\", expected connect or map");
    // Connections by default where they can run: at 256² and equal time on cornell-spheres-point
    // (scripts/equal_time.py, 30 / 60 s, fg 6x6x2 both) RMSE 0.0090 / 0.0076 against the map's
    // 0.0127 / 0.0102 and relMSE 0.00095 / 0.00067 against 0.00148 / 0.00093, judged without the
    // pixels that see the balls first (the reference lacks L S...S E light there): no blur, and
    // eye samples no longer pay a k-nearest search each (1.75x the passes).
    s.causticConnections = fgCaustics && q.caustics != "map";
    applyMethodDefaults(s, plan);
    if (q.globalPhotons) s.globalPhotons = q.globalPhotons;
    if (q.causticPhotons) s.causticPhotons = q.causticPhotons;
    if (q.k) s.globalK = q.k;
    if (q.causticK) s.causticK = q.causticK;
    if (q.lightSamples) s.lightSamples = q.lightSamples;
    if (q.strata && s.method != RenderMethod::PathTracing) s.strata = q.strata;
    if (q.gatherRays && s.method == RenderMethod::FinalGather) s.gatherRays = q.gatherRays;
    if (q.volumeK) s.volumeK = q.volumeK;
    if (s.method == RenderMethod::FinalGather)
        s.closeGather = q.closeGather >= 0.0f ? q.closeGather : kDefaultCloseGather;
    if (s.method == RenderMethod::FinalGather) s.emitterStrata = q.emitterStrata >= 0 ? uint32_t(q.emitterStrata) : 16u;
    if (!q.volumeRadii.empty()) {
        if (q.volumeRadii != "fixed" && q.volumeRadii != "photon")
            throw InputError("render: volume radii \"" + q.volumeRadii + "\", expected fixed or photon");
        s.volumePhotonRadii = q.volumeRadii == "photon";
    }
    if (s.method == RenderMethod::PathTracing) {
        s.passes = q.passes;  // samples per pixel; the path tracer's caller chooses when 0
        return r;
    }
    s.passes = q.passes ? q.passes : (q.seconds > 0 ? 0 : defaultPasses(s.method, width, height));
    s.passes = std::min<uint32_t>(s.passes, 1u << 20);

    auto note = [&](const std::string& what, bool given, const std::string& reason) {
        r.choices.push_back({what, given, given ? std::string() : reason});
    };
    const bool distributed = plan.lensSampling || plan.timeSampling || plan.glossySampling;
    note("passes " + (s.passes ? std::to_string(s.passes) : std::string("until --time")), q.passes || q.seconds > 0,
         s.method == RenderMethod::FinalGather
             ? "10 passes of a 256x256 image (about 40 s on 2 CPU cores), scaled by pixel count, 1 to 64"
         : s.method == RenderMethod::Progressive ? "the radius shrinks by (i+α)/(i+1) per pass; 32 passes ≈ r0 × 0.56"
                                                 : "a quick preview");
    const bool fg = s.method == RenderMethod::FinalGather, cheapEye = fg && fgEyeSamplesAreCheap(s, plan),
               causticEye = fg && fgEyeSamplesReadCaustics(s, plan);
    note("eye samples per pixel per pass " + std::to_string(s.strata * s.strata), q.strata,
         cheapEye ? "6x6: an eye sample costs only its rays here (no caustic map, or caustic connections; no gather "
                    "importance), and at "
                    "equal time the error sits where eye samples decide (edges, shadows, the lamp)"
         : causticEye ? "4x4: each eye sample also pays a k-nearest caustic estimate, so fewer than the 6x6 of a "
                        "scene without caustics; still many, for edges, shadows and the caustic itself"
         : fg && distributed ? "2x2: the plan samples a lens, a shutter or glossy lobes, which need eye samples"
         : fg                ? "one: a k-nearest search per eye sample (gather importance histograms) makes them dear"
         : s.method == RenderMethod::DirectVisualisation ? "2x2: antialiasing for the preview"
         : plan.volumeMap ? "one: in media every eye sample also pays a volume beam estimate"
                          : "2x2: at equal time lamp edges, shadows and caustics need eye samples more than passes");
    if (fg)
        note("gather rays " + std::to_string(s.gatherRays), q.gatherRays,
             cheapEye      ? "2 per eye sample, 72 per pixel and pass, stratified together: the indirect "
                             "noise falls at least as 1/sqrt(passes × samples × gather rays)"
             : causticEye  ? "4 per eye sample, 64 per pixel and pass, stratified together: the indirect "
                             "noise falls at least as 1/sqrt(passes × samples × gather rays)"
             : distributed ? "16 per eye sample, 4 eye samples per pass: the 64 per pixel and pass of a "
                             "scene without them, stratified together; the indirect noise falls at least as "
                             "1/sqrt(passes × samples × gather rays)"
                           : "64, stratified: the indirect part's noise falls at least as 1/sqrt(passes × gather "
                             "rays)");
    // A map the method does not build (mapsFor) emits nothing.
    const RenderMaps built = mapsFor(s.method, plan);
    note("global photons per pass " + std::to_string(built.global ? s.globalPhotons : 0u), q.globalPhotons,
         built.global ? (plan.globalMap ? "the plan's (photoncl analyze): the scene needs a global map"
                                        : "the preview reads all light from the global map")
                      : "no global map needed");
    note("caustic photons per pass " + std::to_string(built.caustic ? s.causticPhotons : 0u), q.causticPhotons,
         built.caustic
             ? "the plan's: the scene has caustics"
             : (plan.causticMap ? "the preview reads caustics from the global map" : "no caustic map needed"));
    note("light samples " + std::to_string(s.lightSamples), q.lightSamples,
         cheapEye || causticEye
             ? "2 shadow rays per eye sample (MIS with the gather rays by the power heuristic): many eye samples "
               "sample the lamp better than many shadow rays from one"
             : "16 shadow rays per diffuse hit: with N gather rays and M light samples the power heuristic gives "
               "the gather rays a share growing with N/M, and gather rays find a small lamp rarely");
    note("k " + std::to_string(s.globalK) + " (caustic " + std::to_string(s.causticK) + ")", q.k || q.causticK,
         causticEye ? "Jensen's 50 photons per estimate; 20 per caustic estimate, made at every eye sample (16 per "
                      "pixel and pass average its noise, and it blurs the caustic less)"
         : fg && s.causticConnections
             ? "Jensen's 50 photons per estimate; 20 per caustic estimate, made only at eye hits seen through "
               "mirrors and glass (many eye samples average its noise)"
             : "Jensen's 50 photons per estimate");
    if (fg)
        note("emitter strata " + std::to_string(s.emitterStrata), q.emitterStrata >= 0,
             "up to 16x16 samples a pass for the light eye paths collect before their diffuse hit, where a probe "
             "saw an emitter's edge: lamp edges dominated fg's RMSE and cost a path tracer nothing");
    if (fg && built.caustic)
        note(std::string("caustics ") + (s.causticConnections ? "connect" : "map"), !q.caustics.empty(),
             "each caustic photon joined to the camera (no blur, and eye samples stay cheap: 6x6; in scenes "
             "that move, at the shutter time its path was emitted at); the caustic map only through mirrors and "
             "glass");
    if (built.volume) {
        note("volume radii " + std::string(s.volumePhotonRadii ? "photon" : "fixed"), !q.volumeRadii.empty(),
             kVolumeRadiiReason);
        note("volume k " + std::to_string(s.volumeK), q.volumeK != 0, kVolumeKReason);
    }
    return r;
}

std::vector<SettingsField> settingsFields(const PhotonRenderSettings& s, const RenderPlan& plan, int width, int height,
                                          uint32_t passes) {
    // A new setting must be added here or among the controls of PhotonRenderSettings that change
    // no pixel; this fails to compile until one of the two is done.
#if defined(__x86_64__) && defined(__GLIBCXX__)
    static_assert(sizeof(PhotonRenderSettings) == 176,
                  "PhotonRenderSettings changed: add the new setting to settingsFields (or say why it changes no "
                  "pixel), then update this size");
#endif
    std::vector<SettingsField> f;
    auto add = [&](const char* key, const std::string& value) { f.push_back({key, value}); };
    add("method", renderMethodName(s.method));
    add("width", std::to_string(width));
    add("height", std::to_string(height));
    add("passes", std::to_string(passes));
    add("seed", std::to_string(s.seed));
    if (s.method == RenderMethod::PathTracing) {
        add("samplesPerPass", "1");
    } else {
        const RenderMaps maps = mapsFor(s.method, plan);
        add("strata", std::to_string(s.strata));
        add("globalPhotons", std::to_string(maps.global ? s.globalPhotons : 0u));
        add("causticPhotons", std::to_string(maps.caustic ? s.causticPhotons : 0u));
        add("k", std::to_string(s.globalK));
        add("causticK", std::to_string(s.causticK));
        add("gatherRays", std::to_string(s.gatherRays));
        add("lightSamples", std::to_string(s.lightSamples));
        add("eyeDepth", std::to_string(s.eyeDepth ? s.eyeDepth : kDefaultEyeDepth));
        add("maxRadius", exact(s.maxRadius));
        add("filter", estimateFilterName(s.filter));
        add("visibility", s.visibility ? "1" : "0");
        add("gatherSource", gatherSourceName(s.gatherSource));
        add("structure", knnStructureWord(s.structure));
        add("gatherImportance", std::to_string(s.histogramCells));
        add("alpha", exact(s.alpha));
        add("progressiveK0", exact(s.progressiveK0));
        add("radius", exact(s.initialRadius));
        if (s.emitterStrata && s.method == RenderMethod::FinalGather)
            add("emitterStrata", std::to_string(s.emitterStrata));  // only when on, as below
        if (s.closeGather > 0.0f && s.method == RenderMethod::FinalGather) add("closeGather", exact(s.closeGather));
        if (s.causticConnections && s.method == RenderMethod::FinalGather && maps.caustic)
            add("causticConnections", "1");  // only when on, so other renders' settings stay as they were
        if (maps.volume) {  // only with media, so the other scenes' settings (and hashes) stay as they were
            add("volumeK", std::to_string(s.volumeK));
            add("volumeRadii", s.volumePhotonRadii ? "photon" : "fixed");
        }
    }
    add("fixedPointBits", std::to_string(FixedPointFilm::kFractionBits));
    return f;
}

std::string settingsText(const PhotonRenderSettings& s, const RenderPlan& plan, int width, int height,
                         uint32_t passes) {
    std::string text;
    for (const SettingsField& f : settingsFields(s, plan, width, height, passes))
        text += (text.empty() ? "" : ";") + f.key + "=" + f.value;
    return text;
}

uint64_t settingsHash(const std::string& text) {
    Fnv1a h;
    h.add(text);
    return h.h;
}

size_t eyeChunkSamples(const PhotonRenderSettings& s, size_t maxAlloc, size_t passSamples) {
    if (s.chunkSamples) return std::min(s.chunkSamples, passSamples);
    const size_t rays = s.method == RenderMethod::FinalGather ? std::max<size_t>(s.gatherRays, 1) : 1u;
    return std::min(std::clamp<size_t>(maxAlloc / 4 / (32u * rays), 256, size_t(1) << 18), passSamples);
}

}  // namespace pcl
