#include "render/photon_renderer.h"
#include "prep/environment_map.h"
#include "prep/media_support.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "core/clock.h"
#include "core/error.h"
#include "core/math.h"
#include "pipeline/camera_rays.h"
#include "pipeline/connect_caustics.h"
#include "pipeline/direct_light.h"
#include "pipeline/eye_paths.h"
#include "pipeline/final_gather.h"
#include "prep/projection_map.h"
#include "prep/volume_estimate_settings.h"
#include "render/device_stages.h"
#include "render/render_stages.h"
#include "render/twin_stages.h"

namespace pcl {

double sceneSurfaceArea(const Scene& scene) {
    double area = 0.0;
    for (const TriangleMesh& m : scene.meshes)
        for (size_t t = 0; t < m.triangleCount(); ++t) {
            Vec3 p0 = m.positions[m.indices[3 * t]], p1 = m.positions[m.indices[3 * t + 1]],
                 p2 = m.positions[m.indices[3 * t + 2]];
            area += 0.5 * length(cross(p1 - p0, p2 - p0));
        }
    for (const Sphere& s : scene.spheres) area += 4.0 * kPiD * double(s.radius) * s.radius;
    return area;
}

double progressiveRadius2(double r0Squared, double alpha, uint32_t pass) {
    double r2 = r0Squared;
    for (uint32_t i = 1; i <= pass; ++i) r2 *= (i + alpha) / (i + 1.0);  // r²_{i+1} = r²_i (i+α)/(i+1)
    return r2;
}

std::string StageTimes::table() const {
    struct Row {
        const char* name;
        double s;
    } rows[] = {{"photon pass", photons}, {"maps", maps},           {"camera", camera},
                {"eye paths", eyePaths},  {"direct light", direct}, {"caustics", caustic},
                {"indirect", indirect},   {"volume", volume},       {"accumulate", accumulate}};
    std::string out;
    char line[128];
    for (const Row& r : rows) {
        std::snprintf(line, sizeof line, "  %-13s %9.3f s  %5.1f %%\n", r.name, r.s,
                      total > 0 ? 100.0 * r.s / total : 0.0);
        out += line;
    }
    std::snprintf(line, sizeof line, "  %-13s %9.3f s\n", "total", total);
    return out + line;
}

PhotonPassOptions photonPassOptions(const PhotonRenderSettings& s, const RenderPlan& plan, uint32_t pass) {
    const RenderMaps maps = mapsFor(s.method, plan);
    PhotonPassOptions po;
    po.buildGlobal = maps.global;
    po.buildCaustic = maps.caustic;
    po.globalPhotons = maps.global ? s.globalPhotons : 0;
    po.causticPhotons = maps.caustic ? s.causticPhotons : 0;
    po.seed = s.seed;
    po.pass = pass;
    po.batchSize = s.photonBatch;
    // Connections in a scene that moves are traced at each caustic photon's own shutter time.
    po.causticTimes = maps.caustic && s.causticConnections && plan.timeSampling;
    return po;
}

MemoryPlan planRenderMemory(const DeviceInfo& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                            const PhotonRenderSettings& s, const RenderPlan& plan) {
    const MemoryPlan memory =
        planMemory(photonPassMemoryRequest(geometry, buffers, photonPassOptions(s, plan)), memoryLimits(device));
    requireMemoryFits(memory);
    return memory;
}

namespace {

// Runs f, waits for the stages' work, adds the wall time to `slot`.
template <class F>
void timed(RenderStages& stages, double& slot, F&& f) {
    auto t = Clock::now();
    f();
    stages.wait();
    slot += since(t);
}

// The global map's photons that arrived after a diffuse bounce: what the progressive method
// reads at the eye hit, beside direct light by shadow rays (the photons straight from the
// lights, and those after specular bounces only, which the caustic map holds).
std::vector<PclPhoton> indirectPhotons(const std::vector<PclPhoton>& global) {
    std::vector<PclPhoton> out;
    out.reserve(global.size());
    for (const PclPhoton& p : global)
        if (p.packed & PCL_PHOTON_AFTER_DIFFUSE) out.push_back(p);
    return out;
}

// The volume photons the eye pass reads: single scattering (bounce 0) is the eye pass's
// next-event estimation, and with a volume caustic map the global volume map leaves the L S+ V
// photons to it (the global pass stores those events too). Dropped before the grid is built, so
// the beam search neither scans them nor sizes its radius by them.
void keepCountedVolumePhotons(PassPhotons& p) {
    const bool causticVolume = !p.volumeCaustic.empty();
    auto counted = [&](const PclPhoton& ph, bool skipSpecular) {
        if (((ph.packed >> PCL_PHOTON_BOUNCE_SHIFT) & 255u) == 0u) return false;
        return !(skipSpecular && (ph.packed & PCL_PHOTON_AFTER_SPECULAR) && !(ph.packed & PCL_PHOTON_AFTER_DIFFUSE));
    };
    auto keep = [&](std::vector<PclPhoton>& v, bool skipSpecular) {
        v.erase(std::remove_if(v.begin(), v.end(), [&](const PclPhoton& ph) { return !counted(ph, skipSpecular); }),
                v.end());
    };
    keep(p.volume, causticVolume);
    keep(p.volumeCaustic, false);
}

bool finite(const PclRadiance& r) { return std::isfinite(r.r) && std::isfinite(r.g) && std::isfinite(r.b); }

// One render: each pass traces fresh photons, decides how its maps are read and runs the eye
// pass in chunks, every stage through `stages` (the device's or the twin's); each sample's sum
// comes from the stages (accumulate), and the film is added to here, on the host, for both.
class PhotonRenderer {
public:
    PhotonRenderer(RenderStages& stages, const Scene& scene, const SceneGeometry& geometry, const SceneBuffers& buffers,
                   const RenderPlan& plan, const PhotonRenderSettings& s)
        : start_(Clock::now()), stages_(stages), scene_(scene), geometry_(geometry), buffers_(buffers), plan_(plan),
          s_(s), maps_(mapsFor(s.method, plan)), width_(scene.camera.width), height_(scene.camera.height),
          spp_(s.strata * s.strata), passSamples_(size_t(width_) * height_ * spp_),
          eyeDepth_(s.eyeDepth ? s.eyeDepth : kDefaultEyeDepth),
          maxRadius_(s.maxRadius > 0 ? s.maxRadius : 0.05f * length(geometry.bounds().extent())),
          area_(sceneSurfaceArea(scene)), table_(buildAreaLightTable(buffers, geometry.primitiveCount())),
          chunk_(stages.chunkSamples(passSamples_)) {
        est_.filter = s.method == RenderMethod::Progressive ? EstimateFilter::Box : s.filter;
        est_.rayEpsilon = buffers.rayEpsilon;
        est_.visibility = s.visibility;
        r0Squared_ = s.initialRadius > 0 ? double(s.initialRadius) * s.initialRadius : 0.0;
    }

    PhotonRenderResult run();

private:
    // The photon vectors a pass's maps read (the stages keep pointers into them for the pass).
    struct PassMaps {
        std::vector<PclPhoton> indirect;  // progressive: the global map's photons after a diffuse bounce
        PassMapSpec spec;
    };

    PassPhotons tracePhotons(uint32_t pass);
    double firstRadius2(const PassPhotons& pass0) const;
    void firstVolumeRadii(const PassPhotons& pass0);
    void volumeRadii(PassPhotons& photons, uint32_t pass);
    void specifyMaps(const PassPhotons& photons, float radius2, PassMaps& m) const;
    // est_ with the first kNN bound for k-nearest queries into a map of `photons` (speed only).
    EstimateSettings hinted(size_t photons, uint32_t k) const {
        EstimateSettings e = est_;
        e.firstRadius2 = firstSearchRadius2(photons, k, area_);
        return e;
    }
    void connectCaustics(uint32_t pass, const std::vector<PclPhoton>& caustic, const std::vector<float>& times,
                         Film& passFilm);
    void findEmitterSpans();
    void emitterEyePaths(const PclCameraParams& camera, size_t first, uint32_t count);
    struct EmitterSpan {
        int begin = 0, end = 0;  // pixels [begin, end) of a row; end 0: none
    };
    EmitterSpan emitterSpan(int y) const { return {emitterSpans_[2 * size_t(y)], emitterSpans_[2 * size_t(y) + 1]}; }
    bool inEmitterSpan(int x, int y) const {
        if (emitterSpans_.empty()) return false;
        const EmitterSpan s = emitterSpan(y);
        return x >= s.begin && x < s.end;
    }
    void emitterSamples(uint32_t pass, Film& passFilm);
    void eyePass(uint32_t pass, const PassMapSpec& maps, Film& passFilm);
    ChunkParts shadeFinalGather(const PassMapSpec& maps, const PclEyeParams& ep, uint32_t count);
    ChunkParts shadeDirectVisualisation(const PassMapSpec& maps, uint32_t count);
    ChunkParts shadeProgressive(const PassMapSpec& maps, const PclEyeParams& ep, uint32_t count);
    void accumulate(size_t first, uint32_t count, ChunkParts parts, Film& passFilm);
    void sumPartsWithAovs(size_t first, uint32_t count, ChunkParts parts);  // into sampleRadiance_
    std::string summary() const;

    const Clock::time_point start_;  // the render's start: its time budget and total count from here
    RenderStages& stages_;
    const Scene& scene_;
    const SceneGeometry& geometry_;
    const SceneBuffers& buffers_;
    const RenderPlan& plan_;
    const PhotonRenderSettings& s_;
    const RenderMaps maps_;
    const int width_, height_;
    const uint32_t spp_;
    const size_t passSamples_;
    const uint32_t eyeDepth_;
    const float maxRadius_;
    const double area_;
    const AreaLightTable table_;
    const size_t chunk_;
    std::vector<PclRadiance> sampleRadiance_;  // a chunk's sums, one per record
    ChunkResult chunkResult_;                  // a chunk's records and parts, kept across chunks and passes
    std::vector<int32_t> emitterSpans_;        // fg with emitterStrata: per row, 2 ints (EmitterSpan: begin,
                                               // end) bounding the pixels whose collected light the emitter
                                               // samples give (empty: none); the accumulate stage reads them
    EstimateSettings est_;
    double r0Squared_ = 0.0;
    // Media: the volume maps' first radius² (global, caustic), from pass 0's photons, and this
    // pass's (shrunk between passes by progressive).
    double volumeR0Squared_[2] = {0.0, 0.0};
    double volumePassRadius2_[2] = {0.0, 0.0};
    std::vector<float> volumePhotonRadius2_[2];  // volumePhotonRadii: this pass's r_p² per photon
    PhotonRenderResult result_;
};

// 1. Photons: a fresh pass, the pass index in its seed.
PassPhotons PhotonRenderer::tracePhotons(uint32_t pass) {
    PassPhotons p = stages_.tracePhotons(photonPassOptions(s_, plan_, pass));
    if (maps_.volume) keepCountedVolumePhotons(p);
    return p;
}

// Progressive r_0: about progressiveK0 photons in the first disc at the mean density of pass 0's
// stored global photons (caustic-only scenes: the caustic map's).
double PhotonRenderer::firstRadius2(const PassPhotons& pass0) const {
    double stored = maps_.global ? pass0.global.size() : pass0.caustic.size();
    double lambda = std::max(stored, 1.0) / std::max(area_, 1e-12);
    return std::min(double(maxRadius_) * maxRadius_, s_.progressiveK0 / (kPiD * lambda));
}

// The volume maps' r_0 (prep/volume_estimate_settings.h, defaultVolumeRadius): about 32 of the
// photons the estimate counts in a ball where the eye looks, from pass 0's map; a map with too few photons for that takes the
// surface maps' largest radius (logged).
void PhotonRenderer::firstVolumeRadii(const PassPhotons& pass0) {
    const std::vector<PclPhoton>* maps[2] = {&pass0.volume, &pass0.volumeCaustic};
    for (int v = 0; v < 2; ++v) {
        if (volumeR0Squared_[v] > 0.0) continue;
        double r = defaultVolumeRadius(*maps[v], geometry_.bounds(), s_.volumeK);
        if (!(r > 0.0)) {
            if (maps[v]->empty()) continue;  // the next pass with photons decides
            r = maxRadius_;
            if (s_.log)
                std::fprintf(stderr, "volume %s map: %zu photons, too few for a radius; using r_max %.4g\n",
                             v == 0 ? "global" : "caustic", maps[v]->size(), r);
        }
        volumeR0Squared_[v] = r * r;
        if (s_.log) std::fprintf(stderr, "volume %s map: beam radius %.4g\n", v == 0 ? "global" : "caustic", r);
    }
}

// The pass's volume radii. Photons that no eye segment can reach are dropped first: segments run
// between the camera's lens and the scene (a hit, or the exit of the bounding sphere the eye pass
// clips escaping rays to), so none leaves the box of that sphere and the lens; a photon further
// than its radius from that box never counts (in cornell-fog most of the global map scatters in
// the fog outside the box, where no eye looks). The margin is 4 r_0: the largest radius (2 r_0)
// and, for the per-photon radii, the reach of a kept photon's k-th neighbour search.
void PhotonRenderer::volumeRadii(PassPhotons& photons, uint32_t pass) {
    const bool progressive = s_.method == RenderMethod::Progressive;
    const double scale2 = progressive ? progressiveRadius2(1.0, s_.alpha, pass) : 1.0;
    Bounds3 reach;
    const Vec3 c = buffers_.sceneCentre, rad(buffers_.sceneRadius);
    reach.extend(c - rad);
    reach.extend(c + rad);
    const Vec3 lens(scene_.camera.apertureRadius);
    reach.extend(scene_.camera.position - lens);
    reach.extend(scene_.camera.position + lens);
    std::vector<PclPhoton>* maps[2] = {&photons.volume, &photons.volumeCaustic};
    for (int v = 0; v < 2; ++v) {
        volumePassRadius2_[v] = volumeR0Squared_[v] * scale2;
        volumePhotonRadius2_[v].clear();
        if (!(volumeR0Squared_[v] > 0.0)) continue;
        const float r0 = float(std::sqrt(volumeR0Squared_[v]));
        const float m = 4.0f * r0;
        std::vector<PclPhoton>& map = *maps[v];
        map.erase(std::remove_if(map.begin(), map.end(),
                                 [&](const PclPhoton& p) {
                                     return p.x < reach.lo.x - m || p.x > reach.hi.x + m || p.y < reach.lo.y - m ||
                                            p.y > reach.hi.y + m || p.z < reach.lo.z - m || p.z > reach.hi.z + m;
                                 }),
                  map.end());
        if (s_.volumePhotonRadii && !map.empty())
            volumePhotonRadius2_[v] = clampVolumePhotonRadii2(
                stages_.volumeKthNeighbourDist2(map, s_.volumeK, 2.0f * r0), 0.25f * r0, 2.0f * r0, float(scale2));
    }
}

// 2. How the method reads the maps: the estimate (k nearest), the fixed-radius estimate
// (progressive) or precomputed irradiance (fg's default gather source).
void PhotonRenderer::specifyMaps(const PassPhotons& photons, float radius2, PassMaps& m) const {
    const bool fg = s_.method == RenderMethod::FinalGather, progressive = s_.method == RenderMethod::Progressive;
    PassMapSpec& spec = m.spec;
    spec.radius2 = radius2;
    if (maps_.global && !photons.global.empty()) {
        MapSpec& g = spec.global;
        if (progressive) {
            m.indirect = indirectPhotons(photons.global);
            if (!m.indirect.empty()) {
                g.reader = MapReader::FixedRadius;
                g.photons = &m.indirect;
                g.maxK = PCL_KNN_MAX_K;
                g.estimate = est_;
            }
        } else if (fg && s_.gatherSource == GatherSource::Precomputed && !s_.visibility) {
            // (With visibility the full estimate is read instead: a precomputed record is found
            // by one nearest lookup with no visibility test, so a record across a thin wall would
            // be read: the stability suite's thin-wall test.)
            g.reader = MapReader::Precomputed;
            g.photons = &photons.global;
            PrecomputedIrradianceOptions& po = g.precomputed;
            po.k = s_.globalK;
            po.maxRadius = maxRadius_;
            po.estimate = hinted(photons.global.size() - photons.global.size() / po.every, s_.globalK);  // the others
        } else {
            g.reader = MapReader::Estimate;
            g.photons = &photons.global;
            g.maxK = s_.globalK;
            g.estimate = hinted(photons.global.size(), s_.globalK);
        }
    }
    // Media: the beam radiance estimate along the eye's medium segments over the photons
    // keepCountedVolumePhotons kept (so the estimate's own skip flags stay off).
    if (maps_.volume) {
        auto volume = [&](const std::vector<PclPhoton>& v, float r2, const std::vector<float>& perPhoton,
                          VolumeMapSpec& out) {
            if (v.empty()) return;
            out.photons = &v;
            out.settings.radius = perPhoton.empty() ? std::sqrt(r2) : volumeReach(perPhoton);
            out.settings.photonRadius2 = perPhoton;
        };
        volume(photons.volume, volumePassRadius2_[0], volumePhotonRadius2_[0], spec.volume);
        volume(photons.volumeCaustic, volumePassRadius2_[1], volumePhotonRadius2_[1], spec.volumeCaustic);
    }
    // The importance histograms read the global map's k nearest photons directly.
    if (fg && s_.histogramCells > 0 && spec.global.reader != MapReader::None) spec.histogramPhotons = &photons.global;
    if (maps_.caustic && !photons.caustic.empty()) {
        MapSpec& c = spec.caustic;
        c.photons = &photons.caustic;
        c.reader = progressive ? MapReader::FixedRadius : MapReader::Estimate;
        c.maxK = progressive ? PCL_KNN_MAX_K : s_.causticK;
        c.estimate = progressive ? est_ : hinted(photons.caustic.size(), s_.causticK);
    }
}

// The eye hits' k-nearest estimate (eye_estimate.cl) over `count` records; records with fewer than
// minDepth specular bounces before their hit get none.
PclEyeEstimateParams eyeEstimateParams(uint32_t count, uint32_t k, float radius2, uint32_t minDepth = 0) {
    PclEyeEstimateParams p{};  // atShutterOpen 0: the caustic map's (globalEstimateParams sets it)
    p.sampleCount = count;
    p.k = k;
    p.maxRadius2 = radius2;
    p.minDepth = minDepth;
    return p;
}

// The global map's: a moving surface's hit asks where it sits at shutter open (shutter_open.h).
PclEyeEstimateParams globalEstimateParams(uint32_t count, uint32_t k, float radius2) {
    PclEyeEstimateParams p = eyeEstimateParams(count, k, radius2);
    p.atShutterOpen = 1;
    return p;
}

// 3. fg at the diffuse eye hits: direct light by shadow rays (MIS with the gather rays for area
// lights), the caustic map, and final gathering into the global map.
ChunkParts PhotonRenderer::shadeFinalGather(const PassMapSpec& m, const PclEyeParams& ep, uint32_t count) {
    ChunkParts parts;
    StageTimes& t = result_.times;
    const bool gather = m.global.reader != MapReader::None;
    PclDirectParams dp = directParams(ep, geometry_, buffers_, table_, s_.lightSamples, gather ? s_.gatherRays : 0u);
    PclGatherParams gp{};
    if (gather) {
        gp = gatherParams(dp, s_.gatherRays, s_.globalK, maxRadius_ * maxRadius_, kDefaultGatherSpecular);
        gp.causticMapRead = maps_.caustic ? 1u : 0u;
        gp.causticSky = skySendsCausticPhotons(buffers_) ? 1u : 0u;
        // r_k: the radius that holds k photons at the pass's mean density.
        const double stored = double(m.global.photons ? m.global.photons->size() : 0);
        if (s_.closeGather > 0.0f && stored > 0.0)
            gp.closeDistance = float(s_.closeGather * std::sqrt(double(s_.globalK) * area_ / (kPiD * stored)));
        if (m.histogramPhotons) {
            gp.histogramCells = dp.histogramCells = s_.histogramCells;
            timed(stages_, t.indirect, [&] { stages_.gatherHistograms(gp); });
        }
    }
    timed(stages_, t.direct, [&] { stages_.directLight(dp); });
    parts.direct = true;
    if (m.caustic.reader != MapReader::None) {
        // With caustic connections the photons lit the directly seen hits already (connectCaustics).
        const PclEyeEstimateParams cq =
            eyeEstimateParams(count, s_.causticK, m.radius2, s_.causticConnections ? 1u : 0u);
        timed(stages_, t.caustic, [&] { stages_.causticEstimate(cq); });
        parts.caustic = true;
    }
    if (gather) {
        timed(stages_, t.indirect, [&] { stages_.finalGather(gp); });
        parts.indirect = true;
    }
    return parts;
}

// 3. direct: the global map read at the diffuse eye hits (it holds direct light too).
ChunkParts PhotonRenderer::shadeDirectVisualisation(const PassMapSpec& m, uint32_t count) {
    ChunkParts parts;
    if (m.caustic.reader != MapReader::None) {
        const PclEyeEstimateParams cq = eyeEstimateParams(count, s_.causticK, m.radius2);
        timed(stages_, result_.times.caustic, [&] { stages_.causticEstimate(cq); });
        parts.caustic = true;
    }
    if (m.global.reader != MapReader::None) {
        const PclEyeEstimateParams gq = globalEstimateParams(count, s_.globalK, m.radius2);
        timed(stages_, result_.times.indirect, [&] { stages_.globalEstimate(gq); });
        parts.indirect = true;
    }
    return parts;
}

// 3. progressive: direct light by shadow rays, then the caustic map and the global map's
// indirect photons with the pass's fixed radius.
ChunkParts PhotonRenderer::shadeProgressive(const PassMapSpec& m, const PclEyeParams& ep, uint32_t count) {
    ChunkParts parts;
    PclDirectParams dp = directParams(ep, geometry_, buffers_, table_, s_.lightSamples, 0u);
    timed(stages_, result_.times.direct, [&] { stages_.directLight(dp); });
    parts.direct = true;
    if (m.caustic.reader != MapReader::None) {
        const PclEyeEstimateParams cq = eyeEstimateParams(count, PCL_KNN_MAX_K, m.radius2);
        timed(stages_, result_.times.caustic, [&] { stages_.causticEstimate(cq); });
        parts.caustic = true;
    }
    if (m.global.reader != MapReader::None) {
        const PclEyeEstimateParams gq = globalEstimateParams(count, PCL_KNN_MAX_K, m.radius2);
        timed(stages_, result_.times.indirect, [&] { stages_.globalEstimate(gq); });
        parts.indirect = true;
    }
    return parts;
}

// 2b. fg's caustic connections: each caustic photon's splat, weighted by the n² samples a pixel's
// pass gives it, so that the film's average adds the splat's estimate once per pass.
void PhotonRenderer::connectCaustics(uint32_t pass, const std::vector<PclPhoton>& caustic,
                                     const std::vector<float>& times, Film& passFilm) {
    const uint64_t passSeed = eyePassSeed(s_.seed, pass);
    PclCameraParams cp = cameraParams(scene_.camera, plan_, passSeed, s_.strata);
    // The records come with times wherever the scene moves (photonPassOptions), even a pass
    // that stored none: the camera samples time there, and a record without one is refused.
    const PclConnectParams params =
        connectParams(geometry_, buffers_, uint32_t(caustic.size()), passSeed, plan_.timeSampling);
    const std::vector<PclSplat> splats = stages_.connectCaustics(params, cp, caustic, times);
    const float weight = float(spp_);
    for (const PclSplat& sp : splats) {
        if (sp.pixel == PCL_NO_SPLAT) continue;
        const int x = int(sp.pixel % uint32_t(width_)), y = int(sp.pixel / uint32_t(width_));
        const Vec3 v(sp.r * weight, sp.g * weight, sp.b * weight);
        passFilm.splat(x, y, v);
        if (s_.aovs) result_.aovs.caustic.splat(x, y, v);
    }
}

// The seed of the emitter samples: apart from the eye pass's, so the two are independent.
uint64_t emitterSeed(uint64_t seed, uint32_t pass) { return eyePassSeed(seed, pass) ^ 0xA5A5A5A5DEADBEEFull; }

// Eye paths alone (camera rays, then the chains to the first diffuse hit) for samples [first,
// first + count) of `camera`, read back into chunkResult_.hits: what the emitter probe and samples need.
void PhotonRenderer::emitterEyePaths(const PclCameraParams& camera, size_t first, uint32_t count) {
    PclCameraParams cp = camera;
    cp.firstSample = static_cast<uint32_t>(first);
    cp.sampleCount = count;
    timed(stages_, result_.times.camera, [&] { stages_.cameraRays(cp); });
    const PclEyeParams ep = eyeParams(cp, geometry_, buffers_, table_, eyeDepth_);
    timed(stages_, result_.times.eyePaths, [&] { stages_.eyePaths(ep); });
    stages_.readChunk(count, ChunkParts{}, chunkResult_);
}

// fg's emitter spans, once per render from a probe of 4 × 4 samples per pixel (its own seed, no
// pass index, so every batch shard finds the same spans): in each row, from the first to the last
// pixel whose samples collect different light before their diffuse hit (an emitter's edge, seen
// directly or through a specular or glossy chain).
void PhotonRenderer::findEmitterSpans() {
    constexpr uint32_t kProbeStrata = 4, kProbe = kProbeStrata * kProbeStrata;
    const size_t pixels = size_t(width_) * height_, total = pixels * kProbe;
    if (uint64_t(pixels) * s_.emitterStrata * s_.emitterStrata >= (uint64_t(1) << 32)) return;
    std::vector<float> lo(pixels, INFINITY), hi(pixels, -INFINITY);
    const PclCameraParams probe = cameraParams(scene_.camera, plan_, emitterSeed(s_.seed, 0xFFFFFFFFu), kProbeStrata);
    for (size_t first = 0; first < total; first += chunk_) {
        const uint32_t count = static_cast<uint32_t>(std::min(chunk_, total - first));
        emitterEyePaths(probe, first, count);
        for (uint32_t i = 0; i < count; ++i) {
            const float* e = chunkResult_.hits[i].emitted;
            const float v = e[0] + e[1] + e[2];
            const size_t p = (first + i) / kProbe;
            lo[p] = std::min(lo[p], v);
            hi[p] = std::max(hi[p], v);
        }
    }
    emitterSpans_.assign(2 * size_t(height_), 0);
    for (int y = 0; y < height_; ++y) {
        int32_t &begin = emitterSpans_[2 * size_t(y)], &end = emitterSpans_[2 * size_t(y) + 1];
        for (int x = 0; x < width_; ++x) {
            const size_t p = size_t(y) * width_ + x;
            if (!(hi[p] > lo[p] + 1e-6f * std::abs(hi[p]))) continue;
            if (end == 0) begin = x;
            end = x + 1;
        }
        result_.emitterPixels += uint32_t(end - begin);
    }
    // M × M as fine as the cap allows while the spans' samples stay within a quarter of the pass's
    // eye samples (they trace eye paths only, no light or gather rays); none when M would not
    // exceed the pass's own n (the glossy floor of cornell-glossy holds 7 400 span pixels: 8 × 8).
    uint32_t m = s_.emitterStrata;
    while (m > s_.strata && uint64_t(result_.emitterPixels) * m * m * 4 > uint64_t(pixels) * s_.strata * s_.strata) --m;
    result_.emitterStrata = m > s_.strata ? m : 0;
    if (result_.emitterPixels == 0 || result_.emitterStrata == 0) {
        emitterSpans_.clear();
        result_.emitterPixels = 0;
        result_.emitterStrata = 0;
    }
}

// Each pass, M × M samples per pixel of the emitter spans for the light collected before the
// diffuse hit (the eye pass leaves it out there), weighted as the pixel's n² samples would be.
void PhotonRenderer::emitterSamples(uint32_t pass, Film& passFilm) {
    const uint32_t m = result_.emitterStrata, mm = m * m;
    const float scale = float(spp_) / float(mm);
    const PclCameraParams camera = cameraParams(scene_.camera, plan_, emitterSeed(s_.seed, pass), m);
    for (int y = 0; y < height_; ++y) {
        const EmitterSpan span = emitterSpan(y);
        if (span.end == 0) continue;
        const size_t base = (size_t(y) * width_ + size_t(span.begin)) * mm;
        const size_t total = size_t(span.end - span.begin) * mm;
        for (size_t done = 0; done < total; done += chunk_) {
            const uint32_t count = static_cast<uint32_t>(std::min(chunk_, total - done));
            emitterEyePaths(camera, base + done, count);
            for (uint32_t i = 0; i < count; ++i) {
                const float* e = chunkResult_.hits[i].emitted;
                const Vec3 v(e[0] * scale, e[1] * scale, e[2] * scale);
                if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
                    ++result_.nonFiniteSamples;
                    continue;
                }
                const int x = int((base + done + i) / mm % size_t(width_));
                passFilm.splat(x, y, v);
                if (s_.aovs) result_.aovs.emitted.splat(x, y, v);
            }
        }
    }
}

// 4. Accumulate: sample s of the pass lies in pixel s / n²; its radiance is emitted + the parts.
void PhotonRenderer::accumulate(size_t first, uint32_t count, ChunkParts parts, Film& passFilm) {
    auto t = Clock::now();
    if (s_.aovs) {
        sumPartsWithAovs(first, count, parts);
    } else {  // the stages sum each sample: 16 bytes a record to read
        SampleRadianceSpec spec;
        spec.first = first;
        spec.count = count;
        spec.samplesPerPixel = spp_;
        spec.width = static_cast<uint32_t>(width_);
        spec.parts = parts;
        spec.emitterSpans = &emitterSpans_;
        stages_.readSampleRadiance(spec, sampleRadiance_);
    }
    for (uint32_t i = 0; i < count; ++i) {
        const size_t pixel = (first + i) / spp_;
        PclRadiance sum = sampleRadiance_[i];
        if (!finite(sum)) {
            ++result_.nonFiniteSamples;
            sum = PclRadiance{0, 0, 0, 0};  // counted and reported; the pixel keeps its weight
        }
        passFilm.add(static_cast<int>(pixel % width_), static_cast<int>(pixel / width_), {sum.r, sum.g, sum.b});
    }
    result_.times.accumulate += since(t);
    result_.samples += count;
}

// AOVs need the parts apart: the records and every part come back, and each sample's sum is
// taken here, as the accumulate stage takes it (kernels/accumulate.cl).
void PhotonRenderer::sumPartsWithAovs(size_t first, uint32_t count, ChunkParts parts) {
    const PclRadiance zero{0, 0, 0, 0};
    stages_.readChunk(count, parts, chunkResult_);
    const std::vector<PclEyeHit>& eye = chunkResult_.hits;
    const std::vector<PclRadiance>&direct = chunkResult_.direct, &caustic = chunkResult_.caustic,
          &indirect = chunkResult_.indirect, &volume = chunkResult_.volume;
    sampleRadiance_.resize(count);
    for (uint32_t i = 0; i < count; ++i) {
        size_t pixel = (first + i) / spp_;
        int x = static_cast<int>(pixel % width_), y = static_cast<int>(pixel / width_);
        const PclEyeHit& h = eye[i];
        PclRadiance em{h.emitted[0], h.emitted[1], h.emitted[2], 0};
        if (inEmitterSpan(x, y)) em = zero;  // emitterSamples gives it
        sampleRadiance_[i] = {em.r + direct[i].r + caustic[i].r + indirect[i].r + volume[i].r,
                              em.g + direct[i].g + caustic[i].g + indirect[i].g + volume[i].g,
                              em.b + direct[i].b + caustic[i].b + indirect[i].b + volume[i].b, 0};
        auto v = [](const PclRadiance& r) { return finite(r) ? Vec3(r.r, r.g, r.b) : Vec3(0.0f); };
        RenderAovs& a = result_.aovs;
        a.direct.add(x, y, v(direct[i]));
        a.caustic.add(x, y, v(caustic[i]));
        a.indirect.add(x, y, v(indirect[i]) + v(volume[i]));  // media: multiple scattering is indirect too
        a.emitted.add(x, y, v(em));
        bool diffuse = h.flags & PCL_EYE_DIFFUSE;
        a.albedo.add(x, y, diffuse ? Vec3(h.albedo[0], h.albedo[1], h.albedo[2]) : Vec3(0.0f));
        a.normal.add(x, y, diffuse ? Vec3(h.nx, h.ny, h.nz) : Vec3(0.0f));
    }
}

// 3. The eye pass, chunk by chunk: camera rays, eye paths to the first diffuse hit, the method's
// parts there, then into the pass's film.
void PhotonRenderer::eyePass(uint32_t pass, const PassMapSpec& maps, Film& passFilm) {
    const uint64_t passSeed = eyePassSeed(s_.seed, pass);
    for (size_t first = 0; first < passSamples_; first += chunk_) {
        const uint32_t count = static_cast<uint32_t>(std::min(chunk_, passSamples_ - first));
        PclCameraParams cp = cameraParams(scene_.camera, plan_, passSeed, s_.strata);
        cp.firstSample = static_cast<uint32_t>(first);
        cp.sampleCount = count;
        timed(stages_, result_.times.camera, [&] { stages_.cameraRays(cp); });
        PclEyeParams ep = eyeParams(cp, geometry_, buffers_, table_, eyeDepth_);
        timed(stages_, result_.times.eyePaths, [&] { stages_.eyePaths(ep); });
        ChunkParts parts;
        switch (s_.method) {
            case RenderMethod::FinalGather: parts = shadeFinalGather(maps, ep, count); break;
            case RenderMethod::DirectVisualisation: parts = shadeDirectVisualisation(maps, count); break;
            case RenderMethod::Progressive: parts = shadeProgressive(maps, ep, count); break;
            case RenderMethod::PathTracing: break;
        }
        if ((maps.volume.photons || maps.volumeCaustic.photons) && ep.volumeSegments > 0) {
            timed(stages_, result_.times.volume, [&] { stages_.volumeEstimate(); });
            parts.volume = true;
        }
        accumulate(first, count, parts, passFilm);
    }
}

namespace {
std::string exact3(float v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.3g", double(v));
    return b;
}
}  // namespace

std::string PhotonRenderer::summary() const {
    const PhotonRenderSettings& s = s_;
    const bool fg = s.method == RenderMethod::FinalGather;
    char line[512];
    std::snprintf(
        line, sizeof line,
        "method %s, %u pass(es)%s, %u spp/pass, global %s, caustic %s, k %u/%u, %s%u gather rays%s%s, "
        "%u light samples, r_max %.4g, %s%s, seed %llu",
        renderMethodName(s.method), s.passes, s.seconds > 0 ? " or time budget" : "", spp_,
        maps_.global ? std::to_string(s.globalPhotons).c_str() : "none",
        maps_.caustic ? std::to_string(s.causticPhotons).c_str() : "none", s.globalK, s.causticK,
        fg ? (s.gatherSource == GatherSource::Precomputed && !s.visibility ? "precomputed irradiance, "
                                                                           : "full estimate, ")
           : "",
        fg ? s.gatherRays : 0u,
        fg && s.histogramCells
            ? (" (importance " + std::to_string(s.histogramCells) + "x" + std::to_string(s.histogramCells) + ")")
                  .c_str()
            : "",
        fg && s.closeGather > 0.0f ? (" (direct light by shadow rays within " + exact3(s.closeGather) + " r_k)").c_str()
                                   : "",
        s.lightSamples, maxRadius_, knnStructureName(s.structure), s.visibility ? ", visibility test" : "",
        static_cast<unsigned long long>(s.seed));
    return line;
}

PhotonRenderResult PhotonRenderer::run() {
    const bool progressive = s_.method == RenderMethod::Progressive;
    result_.sums = FixedPointFilm(width_, height_);
    if (s_.aovs)
        result_.aovs = {Film(width_, height_), Film(width_, height_), Film(width_, height_),
                        Film(width_, height_), Film(width_, height_), Film(width_, height_)};
    result_.chunkSamples = chunk_;
    // A render that starts later (a batch shard, firstPass > 0) traces pass 0's photons once to
    // get the same r_0, so r_0 never depends on which passes a shard holds.
    if (progressive && r0Squared_ == 0.0 && s_.firstPass > 0 && (maps_.global || maps_.caustic)) {
        timed(stages_, result_.times.photons, [&] {
            const PassPhotons pass0 = tracePhotons(0);
            r0Squared_ = firstRadius2(pass0);
            if (maps_.volume) firstVolumeRadii(pass0);
        });
        result_.firstRadius = static_cast<float>(std::sqrt(r0Squared_));
    }
    result_.summary = summary();
    if (s_.method == RenderMethod::FinalGather && s_.emitterStrata > 0) findEmitterSpans();

    Film passFilm;
    const auto passesStart = Clock::now();
    for (uint32_t done = 0;; ++done) {
        if (s_.passes && done >= s_.passes) break;
        if (s_.seconds > 0 && !anotherPassFits(since(start_), s_.seconds, done, since(passesStart))) break;
        if (done > 0 && s_.stop && s_.stop->load()) {
            result_.stopped = true;
            break;
        }
        const uint32_t pass = s_.firstPass + done;  // the global pass index: in every seed
        passFilm = Film(width_, height_);
        PassPhotons photons;
        if (maps_.global || maps_.caustic) {
            double seconds = 0;
            timed(stages_, seconds, [&] { photons = tracePhotons(pass); });
            result_.times.photons += seconds;
            result_.photonPassSeconds.push_back(seconds);
            result_.globalEmitted += photons.globalEmitted;
            result_.causticEmitted += photons.causticEmitted;
            result_.globalStored += photons.global.size();
            result_.causticStored += photons.caustic.size();
        }
        float radius2 = maxRadius_ * maxRadius_;
        if (progressive) {
            if (r0Squared_ == 0.0) {  // pass 0 (firstPass > 0 computed it above)
                r0Squared_ = firstRadius2(photons);
                result_.firstRadius = static_cast<float>(std::sqrt(r0Squared_));
            }
            radius2 = static_cast<float>(progressiveRadius2(r0Squared_, s_.alpha, pass));
            result_.lastRadius = std::sqrt(radius2);
        }
        if (maps_.volume) {
            firstVolumeRadii(photons);
            timed(stages_, result_.times.maps, [&] { volumeRadii(photons, pass); });
        }
        PassMaps maps;
        specifyMaps(photons, radius2, maps);
        timed(stages_, result_.times.maps, [&] { stages_.buildMaps(maps.spec); });
        if (s_.causticConnections && maps.spec.caustic.photons)
            timed(stages_, result_.times.caustic,
                  [&] { connectCaustics(pass, *maps.spec.caustic.photons, photons.causticTimes, passFilm); });
        eyePass(pass, maps.spec, passFilm);
        if (!emitterSpans_.empty()) emitterSamples(pass, passFilm);
        // 5. The pass's sums, rounded once to fixed point, join the render's (exact: any
        // grouping of passes gives the same bits).
        {
            auto t = Clock::now();
            result_.sums.addPass(passFilm);
            result_.times.accumulate += since(t);
        }
        result_.passes = done + 1;
        double fraction = s_.passes ? double(result_.passes) / s_.passes : 0.0;
        if (s_.seconds > 0) fraction = std::max(fraction, std::min(1.0, since(start_) / s_.seconds));
        if (s_.log)
            std::fprintf(stderr, "pass %u: %zu global + %zu caustic photons stored%s\n", pass, photons.global.size(),
                         photons.caustic.size(),
                         progressive ? (", radius " + std::to_string(std::sqrt(radius2))).c_str() : "");
        if (s_.onPass) s_.onPass(result_.passes, std::min(1.0, fraction));
    }
    if (!result_.stopped && s_.stop && s_.stop->load() && s_.passes && result_.passes < s_.passes)
        result_.stopped = true;
    passFilm = Film();  // (host memory: a 4K film is 265 MB)
    result_.film = result_.sums.toFilm();
    result_.times.total = since(start_);
    return std::move(result_);
}

}  // namespace

namespace {

// Before any stage is built: a photon method and valid settings.
void requirePhotonRender(const PhotonRenderSettings& settings, const Scene& scene) {
    if (settings.method == RenderMethod::PathTracing)
        throw InternalError("renderPhotonMapped: the path tracer is render/path_render.h, not a photon method");
    validateRenderSettings(settings);
    if (settings.method == RenderMethod::FinalGather)
        refuseMediaWithoutPathTracer(scene, "--method fg (its gather rays do not carry media yet)");
    refuseEnvironmentInMediaWithoutPathTracer(scene, std::string("--method ") + renderMethodName(settings.method));
}

}  // namespace

PhotonRenderResult renderPhotonMapped(RenderStages& stages, const Scene& scene, const SceneGeometry& geometry,
                                      const SceneBuffers& buffers, const RenderPlan& plan,
                                      const PhotonRenderSettings& settings) {
    requirePhotonRender(settings, scene);
    return PhotonRenderer(stages, scene, geometry, buffers, plan, settings).run();
}

PhotonRenderResult renderPhotonMapped(Device& device, const Scene& scene, const SceneGeometry& geometry,
                                      const SceneBuffers& buffers, const RenderPlan& plan,
                                      const PhotonRenderSettings& settings) {
    requirePhotonRender(settings, scene);
    DeviceRenderStages stages(device, scene, geometry, buffers, settings);
    return renderPhotonMapped(stages, scene, geometry, buffers, plan, settings);
}

PhotonRenderResult renderPhotonMappedTwin(const Scene& scene, const SceneGeometry& geometry,
                                          const SceneBuffers& buffers, const RenderPlan& plan,
                                          const PhotonRenderSettings& settings) {
    requirePhotonRender(settings, scene);
    TwinRenderStages stages(scene, geometry, buffers);
    return renderPhotonMapped(stages, scene, geometry, buffers, plan, settings);
}

}  // namespace pcl
