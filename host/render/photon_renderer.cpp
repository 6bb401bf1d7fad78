#include "render/photon_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include "core/clock.h"
#include "core/error.h"
#include "core/math.h"
#include "pipeline/camera_rays.h"
#include "pipeline/device_scene.h"
#include "pipeline/direct_light.h"
#include "pipeline/eye_estimate.h"
#include "pipeline/eye_paths.h"
#include "pipeline/final_gather.h"
#include "pipeline/irradiance_source.h"
#include "pipeline/photon_pass.h"
#include "pipeline/precomputed_irradiance.h"
#include "render/fixed_radius_source.h"

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
    } rows[] = {{"photon pass", photons}, {"maps", maps},        {"camera", camera},     {"eye paths", eyePaths},
                {"direct light", direct}, {"caustics", caustic}, {"indirect", indirect}, {"accumulate", accumulate}};
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

// Runs f, waits for the device, adds the wall time to `slot`.
template <class F>
void timed(Device& device, double& slot, F&& f) {
    auto t = Clock::now();
    f();
    device.finish();
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

bool finite(const PclRadiance& r) { return std::isfinite(r.r) && std::isfinite(r.g) && std::isfinite(r.b); }

// One render: the scene's device buffers and the eye buffers live for the whole render; each
// pass traces fresh photons, builds the maps it needs and runs the eye pass in chunks.
class PhotonRenderer {
public:
    PhotonRenderer(Device& device, const Scene& scene, const SceneGeometry& geometry, const SceneBuffers& buffers,
                   const RenderPlan& plan, const PhotonRenderSettings& s)
        : start_(Clock::now()), device_(device), scene_(scene), geometry_(geometry), buffers_(buffers), plan_(plan),
          s_(s), maps_(mapsFor(s.method, plan)), width_(scene.camera.width), height_(scene.camera.height),
          spp_(s.strata * s.strata), passSamples_(size_t(width_) * height_ * spp_),
          eyeDepth_(s.eyeDepth ? s.eyeDepth : kDefaultEyeDepth),
          maxRadius_(s.maxRadius > 0 ? s.maxRadius : 0.05f * length(geometry.bounds().extent())),
          area_(sceneSurfaceArea(scene)), dscene_(device, geometry, buffers),
          table_(buildAreaLightTable(buffers, geometry.primitiveCount())), lights_(device, table_) {
        chunk_ = eyeChunkSamples(s, device.info().maxAlloc, passSamples_);
        rays_ = device.allocate<PclRay>(chunk_, CL_MEM_READ_WRITE, "render: camera rays");
        hits_ = device.allocate<PclEyeHit>(chunk_, CL_MEM_READ_WRITE, "render: eye hits");
        directRad_ = device.allocate<PclRadiance>(chunk_, CL_MEM_READ_WRITE, "render: direct radiance");
        causticRad_ = device.allocate<PclRadiance>(chunk_, CL_MEM_READ_WRITE, "render: caustic radiance");
        indirectRad_ = device.allocate<PclRadiance>(chunk_, CL_MEM_READ_WRITE, "render: indirect radiance");
        est_.filter = s.method == RenderMethod::Progressive ? EstimateFilter::Box : s.filter;
        est_.rayEpsilon = buffers.rayEpsilon;
        est_.visibility = s.visibility;
        r0Squared_ = s.initialRadius > 0 ? double(s.initialRadius) * s.initialRadius : 0.0;
    }

    PhotonRenderResult run();

private:
    // The maps of one pass and the irradiance sources that read them.
    struct PassMaps {
        std::unique_ptr<PhotonMapOnDevice> global, caustic, histogram;
        std::unique_ptr<DeviceIrradianceMap> irradiance;
        std::shared_ptr<IrradianceSource> globalSource, causticSource;
        float radius2 = 0.0f;  // the search radius² of the pass (progressive: the schedule's)
    };
    // Which parts a chunk's eye samples got (the others are 0).
    struct ChunkParts {
        bool direct = false, caustic = false, indirect = false;
    };

    PhotonMaps tracePhotons(uint32_t pass);
    double firstRadius2(const PhotonMaps& pass0) const;
    PassMaps buildMaps(const PhotonMaps& photons, float radius2);
    // est_ with the first kNN bound for k-nearest queries into a map of `photons` (speed only).
    EstimateSettings hinted(size_t photons, uint32_t k) const {
        EstimateSettings e = est_;
        e.firstRadius2 = firstSearchRadius2(photons, k, area_);
        return e;
    }
    void eyePass(uint32_t pass, const PassMaps& maps, Film& passFilm);
    ChunkParts shadeFinalGather(const PassMaps& maps, const PclEyeParams& ep, uint32_t count);
    ChunkParts shadeDirectVisualisation(const PassMaps& maps, uint32_t count);
    ChunkParts shadeProgressive(const PassMaps& maps, const PclEyeParams& ep, uint32_t count);
    void accumulate(size_t first, uint32_t count, ChunkParts parts, Film& passFilm);
    std::string summary() const;

    const Clock::time_point start_;  // the render's start: its time budget and total count from here
    Device& device_;
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
    DeviceScene dscene_;
    AreaLightTable table_;
    DeviceAreaLights lights_;
    size_t chunk_ = 0;
    cl::Buffer rays_, hits_, directRad_, causticRad_, indirectRad_;
    std::vector<PclEyeHit> hostHits_;        // a chunk's downloads, kept across chunks and passes
    std::vector<PclRadiance> hostParts_[3];  // direct, caustic, indirect
    EstimateSettings est_;
    double r0Squared_ = 0.0;
    PhotonRenderResult result_;
};

// 1. Photons: a fresh pass, the pass index in its seed.
PhotonMaps PhotonRenderer::tracePhotons(uint32_t pass) {
    return runPhotonPass(device_, geometry_, buffers_, photonPassOptions(s_, plan_, pass));
}

// Progressive r_0: about progressiveK0 photons in the first disc at the mean density of pass 0's
// stored global photons (caustic-only scenes: the caustic map's).
double PhotonRenderer::firstRadius2(const PhotonMaps& pass0) const {
    double stored = maps_.global ? pass0.global.size() : pass0.caustic.size();
    double lambda = std::max(stored, 1.0) / std::max(area_, 1e-12);
    return std::min(double(maxRadius_) * maxRadius_, s_.progressiveK0 / (kPiD * lambda));
}

// 2. The maps the method reads and their irradiance sources.
PhotonRenderer::PassMaps PhotonRenderer::buildMaps(const PhotonMaps& photons, float radius2) {
    const bool fg = s_.method == RenderMethod::FinalGather, progressive = s_.method == RenderMethod::Progressive;
    PassMaps m;
    m.radius2 = radius2;
    const float searchRadius = std::sqrt(radius2);
    if (maps_.global && !photons.global.empty()) {
        if (progressive) {
            std::vector<PclPhoton> indirect = indirectPhotons(photons.global);
            if (!indirect.empty()) {
                m.global = std::make_unique<PhotonMapOnDevice>(device_, indirect, s_.structure, searchRadius);
                m.globalSource = fixedRadiusSource(*m.global, PCL_KNN_MAX_K, est_, radius2, &dscene_);
            }
        } else if (fg && s_.gatherSource == GatherSource::Precomputed && !s_.visibility) {
            // (With visibility the full estimate is read instead: a precomputed record is found
            // by one nearest lookup with no visibility test, so a record across a thin wall would
            // be read: the stability suite's thin-wall test.)
            PrecomputedIrradianceOptions po;
            po.k = s_.globalK;
            po.maxRadius = maxRadius_;
            po.estimate = hinted(photons.global.size() - photons.global.size() / po.every, s_.globalK);  // the others
            m.irradiance =
                std::make_unique<DeviceIrradianceMap>(precomputeIrradiance(device_, photons.global, po, &dscene_));
            m.globalSource = precomputedIrradianceSource(*m.irradiance);
        } else {
            m.global = std::make_unique<PhotonMapOnDevice>(device_, photons.global, s_.structure, searchRadius);
            m.globalSource =
                estimateIrradianceSource(*m.global, s_.globalK, hinted(photons.global.size(), s_.globalK), &dscene_);
        }
    }
    if (fg && s_.histogramCells > 0 && m.globalSource) {
        // The importance histograms read the global map's k nearest photons directly.
        m.histogram = std::make_unique<PhotonMapOnDevice>(device_, photons.global, s_.structure, searchRadius);
    }
    if (maps_.caustic && !photons.caustic.empty()) {
        m.caustic = std::make_unique<PhotonMapOnDevice>(device_, photons.caustic, s_.structure, searchRadius);
        m.causticSource = progressive ? fixedRadiusSource(*m.caustic, PCL_KNN_MAX_K, est_, radius2, &dscene_)
                                      : estimateIrradianceSource(*m.caustic, s_.causticK,
                                                                 hinted(photons.caustic.size(), s_.causticK), &dscene_);
    }
    return m;
}

// 3. fg at the diffuse eye hits: direct light by shadow rays (MIS with the gather rays for area
// lights), the caustic map, and final gathering into the global map.
PhotonRenderer::ChunkParts PhotonRenderer::shadeFinalGather(const PassMaps& m, const PclEyeParams& ep, uint32_t count) {
    ChunkParts parts;
    StageTimes& t = result_.times;
    const bool gather = static_cast<bool>(m.globalSource);
    PclDirectParams dp = directParams(ep, geometry_, buffers_, table_, s_.lightSamples, gather ? s_.gatherRays : 0u);
    PclGatherParams gp{};
    cl::Buffer histograms;
    if (gather) {
        gp = gatherParams(dp, s_.gatherRays, s_.globalK, maxRadius_ * maxRadius_, kDefaultGatherSpecular);
        gp.causticMapRead = maps_.caustic ? 1u : 0u;
        if (m.histogram) {
            gp.histogramCells = dp.histogramCells = s_.histogramCells;
            timed(device_, t.indirect, [&] { histograms = buildGatherHistograms(device_, *m.histogram, gp, hits_); });
        }
    }
    timed(device_, t.direct, [&] {
        if (m.histogram) directLight(device_, dscene_, lights_, dp, hits_, histograms, directRad_);
        else directLight(device_, dscene_, lights_, dp, hits_, directRad_);
    });
    parts.direct = true;
    if (m.causticSource) {
        PclEyeEstimateParams cq{count, s_.causticK, m.radius2, 0};
        timed(device_, t.caustic, [&] { causticRadiance(device_, cq, hits_, *m.causticSource, causticRad_); });
        parts.caustic = true;
    }
    if (gather) {
        timed(device_, t.indirect, [&] {
            if (m.histogram)
                finalGather(device_, dscene_, lights_, gp, hits_, histograms, *m.globalSource, indirectRad_);
            else finalGather(device_, dscene_, lights_, gp, hits_, *m.globalSource, indirectRad_);
        });
        parts.indirect = true;
    }
    return parts;
}

// 3. direct: the global map read at the diffuse eye hits (it holds direct light too).
PhotonRenderer::ChunkParts PhotonRenderer::shadeDirectVisualisation(const PassMaps& m, uint32_t count) {
    ChunkParts parts;
    if (m.causticSource) {
        PclEyeEstimateParams cq{count, s_.causticK, m.radius2, 0};
        timed(device_, result_.times.caustic,
              [&] { causticRadiance(device_, cq, hits_, *m.causticSource, causticRad_); });
        parts.caustic = true;
    }
    if (m.globalSource) {
        PclEyeEstimateParams gq{count, s_.globalK, m.radius2, 0};
        timed(device_, result_.times.indirect,
              [&] { estimateAtEyeHits(device_, gq, hits_, *m.globalSource, indirectRad_); });
        parts.indirect = true;
    }
    return parts;
}

// 3. progressive: direct light by shadow rays, then the caustic map and the global map's
// indirect photons with the pass's fixed radius.
PhotonRenderer::ChunkParts PhotonRenderer::shadeProgressive(const PassMaps& m, const PclEyeParams& ep, uint32_t count) {
    ChunkParts parts;
    PclDirectParams dp = directParams(ep, geometry_, buffers_, table_, s_.lightSamples, 0u);
    timed(device_, result_.times.direct, [&] { directLight(device_, dscene_, lights_, dp, hits_, directRad_); });
    parts.direct = true;
    if (m.causticSource) {
        PclEyeEstimateParams cq{count, PCL_KNN_MAX_K, m.radius2, 0};
        timed(device_, result_.times.caustic,
              [&] { causticRadiance(device_, cq, hits_, *m.causticSource, causticRad_); });
        parts.caustic = true;
    }
    if (m.globalSource) {
        PclEyeEstimateParams gq{count, PCL_KNN_MAX_K, m.radius2, 0};
        timed(device_, result_.times.indirect,
              [&] { estimateAtEyeHits(device_, gq, hits_, *m.globalSource, indirectRad_); });
        parts.indirect = true;
    }
    return parts;
}

// 4. Accumulate: sample s of the pass lies in pixel s / n²; its radiance is emitted + the parts.
void PhotonRenderer::accumulate(size_t first, uint32_t count, ChunkParts parts, Film& passFilm) {
    auto t = Clock::now();
    const PclRadiance zero{0, 0, 0, 0};
    std::vector<PclEyeHit>& eye = hostHits_;
    device_.downloadInto(hits_, count, eye);
    auto part = [&](bool have, cl::Buffer& b, std::vector<PclRadiance>& v) -> const std::vector<PclRadiance>& {
        if (have) device_.downloadInto(b, count, v);
        else v.assign(count, zero);
        return v;
    };
    const std::vector<PclRadiance>&direct = part(parts.direct, directRad_, hostParts_[0]),
          &caustic = part(parts.caustic, causticRad_, hostParts_[1]),
          &indirect = part(parts.indirect, indirectRad_, hostParts_[2]);
    for (uint32_t i = 0; i < count; ++i) {
        size_t pixel = (first + i) / spp_;
        int x = static_cast<int>(pixel % width_), y = static_cast<int>(pixel / width_);
        const PclEyeHit& h = eye[i];
        PclRadiance em{h.emitted[0], h.emitted[1], h.emitted[2], 0};
        PclRadiance sum{em.r + direct[i].r + caustic[i].r + indirect[i].r,
                        em.g + direct[i].g + caustic[i].g + indirect[i].g,
                        em.b + direct[i].b + caustic[i].b + indirect[i].b, 0};
        if (!finite(sum)) {
            ++result_.nonFiniteSamples;
            sum = zero;  // counted and reported; the pixel keeps its weight
        }
        passFilm.add(x, y, {sum.r, sum.g, sum.b});
        if (s_.aovs) {
            auto v = [](const PclRadiance& r) { return finite(r) ? Vec3(r.r, r.g, r.b) : Vec3(0.0f); };
            RenderAovs& a = result_.aovs;
            a.direct.add(x, y, v(direct[i]));
            a.caustic.add(x, y, v(caustic[i]));
            a.indirect.add(x, y, v(indirect[i]));
            a.emitted.add(x, y, v(em));
            bool diffuse = h.flags & PCL_EYE_DIFFUSE;
            a.albedo.add(x, y, diffuse ? Vec3(h.albedo[0], h.albedo[1], h.albedo[2]) : Vec3(0.0f));
            a.normal.add(x, y, diffuse ? Vec3(h.nx, h.ny, h.nz) : Vec3(0.0f));
        }
    }
    result_.times.accumulate += since(t);
    result_.samples += count;
}

// 3. The eye pass, chunk by chunk: camera rays, eye paths to the first diffuse hit, the method's
// parts there, then into the pass's film.
void PhotonRenderer::eyePass(uint32_t pass, const PassMaps& maps, Film& passFilm) {
    const uint64_t passSeed = eyePassSeed(s_.seed, pass);
    for (size_t first = 0; first < passSamples_; first += chunk_) {
        const uint32_t count = static_cast<uint32_t>(std::min(chunk_, passSamples_ - first));
        PclCameraParams cp = cameraParams(scene_.camera, plan_, passSeed, s_.strata);
        cp.firstSample = static_cast<uint32_t>(first);
        cp.sampleCount = count;
        timed(device_, result_.times.camera, [&] { generateCameraRays(device_, cp, rays_); });
        PclEyeParams ep = eyeParams(cp, geometry_, buffers_, table_, eyeDepth_);
        timed(device_, result_.times.eyePaths, [&] { traceEyePaths(device_, dscene_, lights_, ep, rays_, hits_); });
        ChunkParts parts;
        switch (s_.method) {
            case RenderMethod::FinalGather: parts = shadeFinalGather(maps, ep, count); break;
            case RenderMethod::DirectVisualisation: parts = shadeDirectVisualisation(maps, count); break;
            case RenderMethod::Progressive: parts = shadeProgressive(maps, ep, count); break;
            case RenderMethod::PathTracing: break;
        }
        accumulate(first, count, parts, passFilm);
    }
}

std::string PhotonRenderer::summary() const {
    const PhotonRenderSettings& s = s_;
    const bool fg = s.method == RenderMethod::FinalGather;
    char line[512];
    std::snprintf(line, sizeof line,
                  "method %s, %u pass(es)%s, %u spp/pass, global %s, caustic %s, k %u/%u, %s%u gather rays%s, "
                  "%u light samples, r_max %.4g, %s%s, seed %llu",
                  renderMethodName(s.method), s.passes, s.seconds > 0 ? " or time budget" : "", spp_,
                  maps_.global ? std::to_string(s.globalPhotons).c_str() : "none",
                  maps_.caustic ? std::to_string(s.causticPhotons).c_str() : "none", s.globalK, s.causticK,
                  fg ? (s.gatherSource == GatherSource::Precomputed && !s.visibility ? "precomputed irradiance, "
                                                                                     : "full estimate, ")
                     : "",
                  fg ? s.gatherRays : 0u,
                  fg && s.histogramCells ? (" (importance " + std::to_string(s.histogramCells) + "x" +
                                            std::to_string(s.histogramCells) + ")")
                                               .c_str()
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
        timed(device_, result_.times.photons, [&] { r0Squared_ = firstRadius2(tracePhotons(0)); });
        result_.firstRadius = static_cast<float>(std::sqrt(r0Squared_));
    }
    result_.summary = summary();

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
        PhotonMaps photons;
        if (maps_.global || maps_.caustic) {
            timed(device_, result_.times.photons, [&] { photons = tracePhotons(pass); });
            result_.globalEmitted += photons.stats.global.emitted;
            result_.causticEmitted += photons.stats.caustic.emitted;
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
        PassMaps maps;
        timed(device_, result_.times.maps, [&] { maps = buildMaps(photons, radius2); });
        eyePass(pass, maps, passFilm);
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

PhotonRenderResult renderPhotonMapped(Device& device, const Scene& scene, const SceneGeometry& geometry,
                                      const SceneBuffers& buffers, const RenderPlan& plan,
                                      const PhotonRenderSettings& settings) {
    if (settings.method == RenderMethod::PathTracing)
        throw InternalError("renderPhotonMapped: the path tracer is render/path_render.h, not a photon method");
    validateRenderSettings(settings);
    return PhotonRenderer(device, scene, geometry, buffers, plan, settings).run();
}

}  // namespace pcl
