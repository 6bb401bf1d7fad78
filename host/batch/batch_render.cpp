#include "batch/batch_render.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "pipeline/camera_rays.h"
#include "pipeline/estimate.h"
#include "pipeline/eye_paths.h"
#include "pipeline/memory_plan.h"
#include "pipeline/photon_pass.h"
#include "pipeline/projection_map.h"
#include "reference/path_tracer.h"
#include "scene/json_parse.h"
#include "scene/load_scene.h"

namespace pcl {
namespace {

template <class T>
void hashVector(Fnv1a& h, const std::vector<T>& v) {
    uint64_t n = v.size();
    h.add(&n, sizeof n);
    h.add(v.data(), v.size() * sizeof(T));
}

std::string utcNow() {
    std::time_t t = std::time(nullptr);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
    return buf;
}

std::string hostName() {
    char buf[256] = {0};
    if (::gethostname(buf, sizeof buf - 1) != 0) return "unknown";
    return buf;
}

// %a: the exact bits of a float, so two settings texts are equal exactly when the values are.
std::string exact(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%a", v);
    return buf;
}

}  // namespace

uint64_t hostMaxRssBytes() {
    rusage u{};
    ::getrusage(RUSAGE_SELF, &u);
    return uint64_t(u.ru_maxrss) * 1024;  // Linux reports KiB
}

BatchScene loadBatchScene(const BatchJob& job) {
    BatchScene b;
    b.job = job;
    b.scene = loadScene(job.scene);
    b.scene.camera.width = job.width;
    b.scene.camera.height = job.height;
    b.geometry = SceneGeometry::build(b.scene);
    b.buffers = buildSceneBuffers(b.scene, b.geometry);
    buildProjectionMaps(b.scene, b.geometry, b.buffers);
    b.plan = makePlan(b.scene, classifyLightPaths(b.scene, b.geometry, b.buffers));

    // The settings exactly as `photoncl render` resolves them: the render defaults for the
    // method, then every value the job gives (applyRenderDefaults with overrides).
    PhotonRenderSettings& s = b.settings;
    s.method = parseRenderMethod(job.method);
    s.seed = job.seed;
    s.filter = parseEstimateFilter(job.filter);
    s.visibility = job.visibility;
    s.gatherSource = job.gatherSource == "estimate" ? GatherSource::Estimate : GatherSource::Precomputed;
    s.alpha = job.alpha;
    s.histogramCells = job.gatherImportance;
    s.initialRadius = job.radius;
    s.maxRadius = job.maxRadius;
    s.structure = job.structure == "hash-grid" ? KnnStructure::HashGrid : KnnStructure::KdTree;
    applyRenderDefaults(s, b.plan,
                        {job.globalPhotons, job.causticPhotons, job.k, job.causticK, job.lightSamples, job.strata,
                         job.gatherRays});
    s.passes = job.passes;

    // Every setting that changes a pixel, at its exact value; the photon batch and the buffer
    // cap are left out (they change launch counts, not results: DESIGN.md, Memory), and so is
    // the shard count (a pass is the same pass in any shard).
    const RenderMaps maps = mapsFor(s.method, b.plan);
    std::ostringstream t;
    if (s.method == RenderMethod::PathTracing)  // (its own settings are fixed: depth, roulette, MIS)
        t << "method=path;width=" << job.width << ";height=" << job.height << ";passes=" << job.passes
          << ";seed=" << s.seed << ";samplesPerPass=1;fixedPointBits=" << FixedPointFilm::kFractionBits;
    else
    t << "method=" << renderMethodName(s.method) << ";width=" << job.width << ";height=" << job.height
      << ";passes=" << job.passes << ";seed=" << s.seed << ";strata=" << s.strata
      << ";globalPhotons=" << (maps.global ? s.globalPhotons : 0u) << ";causticPhotons=" << (maps.caustic ? s.causticPhotons : 0u)
      << ";k=" << s.globalK << ";causticK=" << s.causticK << ";gatherRays=" << s.gatherRays
      << ";lightSamples=" << s.lightSamples << ";eyeDepth=" << (s.eyeDepth ? s.eyeDepth : kDefaultEyeDepth)
      << ";maxRadius=" << exact(s.maxRadius) << ";filter=" << job.filter << ";visibility=" << s.visibility
      << ";gatherSource=" << job.gatherSource << ";structure=" << job.structure << ";gatherImportance=" << s.histogramCells << ";alpha=" << exact(s.alpha)
      << ";progressiveK0=" << exact(s.progressiveK0) << ";radius=" << exact(s.initialRadius)
      << ";fixedPointBits=" << FixedPointFilm::kFractionBits;
    b.settingsText = t.str();
    Fnv1a sh;
    sh.add(b.settingsText);
    b.settingsHash = sh.h;

    Fnv1a h;
    h.add(readTextFile(job.scene));
    for (const TriangleMesh& m : b.scene.meshes) {
        hashVector(h, m.positions);
        hashVector(h, m.normals);
        hashVector(h, m.indices);
    }
    hashVector(h, b.buffers.materials);
    hashVector(h, b.buffers.primInfo);
    hashVector(h, b.buffers.lights);
    hashVector(h, b.buffers.projCells);
    PclCameraParams cp = cameraParams(b.scene.camera, b.plan, 0, 1);
    h.add(&cp, sizeof cp);
    b.sceneHash = h.h;
    return b;
}

namespace {

// The path tracer's passes [first, first + count): one sample per pixel each, on the host.
PhotonRenderResult renderPathPasses(const BatchScene& bs, uint32_t first, uint32_t count, int threads,
                                    const std::atomic<bool>* stop, const std::function<void(uint32_t, double)>& onPass) {
    auto start = std::chrono::steady_clock::now();
    PhotonRenderResult r;
    r.sums = FixedPointFilm(bs.job.width, bs.job.height);
    PathTracerSettings pt;
    pt.seed = bs.settings.seed;
    pt.samplesPerPixel = 1;
    pt.threads = threads;
    for (uint32_t done = 0; done < count; ++done) {
        if (done > 0 && stop && stop->load()) {
            r.stopped = true;
            break;
        }
        pt.firstSample = static_cast<int>(first + done);
        PathTracerStats stats;
        r.sums.addPass(PathTracer(bs.scene, bs.geometry, pt).render(&stats));
        r.samples += stats.samples;
        r.nonFiniteSamples += stats.discardedSamples;
        r.passes = done + 1;
        if (onPass) onPass(r.passes, double(r.passes) / count);
    }
    r.times.total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

}  // namespace

ShardData renderShard(Device* device, const BatchScene& bs, uint32_t index, PassRange range,
                      const ShardData* resumeFrom, const ShardRunOptions& options) {
    const bool path = bs.settings.method == RenderMethod::PathTracing;
    if (!path && !device) throw InputError("batch: method " + bs.job.method + " needs an OpenCL device");
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    const BatchJob& job = bs.job;
    ShardData out;
    out.job = job.path;
    out.index = index;
    out.shards = job.shards;
    out.passes = job.passes;
    out.range = range;
    out.method = job.method;
    out.width = job.width;
    out.height = job.height;
    out.seed = job.seed;
    out.sceneHash = bs.sceneHash;
    out.settingsHash = bs.settingsHash;
    out.settings = bs.settingsText;
    out.version = PHOTONCL_VERSION;
    out.device = path ? kPathTracerDevice : device->info().name;
    out.platform = path ? "host" : device->info().platform;
    out.host = hostName();
    nlohmann::json runs = nlohmann::json::array();
    if (resumeFrom) {
        // A partial shard of the same range: its passes stay, the rest are rendered and added
        // (fixed point: the sum is the same bits as rendering the range at once). Its film is
        // added after the render, not copied now: no third copy of the sums while rendering.
        out.passesDone = resumeFrom->passesDone;
        out.globalEmitted = resumeFrom->globalEmitted;
        out.causticEmitted = resumeFrom->causticEmitted;
        out.globalStored = resumeFrom->globalStored;
        out.causticStored = resumeFrom->causticStored;
        out.samples = resumeFrom->samples;
        out.nonFiniteSamples = resumeFrom->nonFiniteSamples;
        if (resumeFrom->accounting.contains("runs")) runs = resumeFrom->accounting["runs"];
    }
    const uint32_t first = range.first + out.passesDone;

    PhotonRenderSettings s = bs.settings;
    s.firstPass = first;
    s.passes = range.end - first;
    s.seconds = 0.0;
    s.stop = options.stop;
    s.log = options.log;
    s.onPass = [&](uint32_t done, double) {
        if (options.onPass) options.onPass(out.passesDone + done, range.count());
    };

    // The memory plan of one photon pass (as render does): fails before any work, with advice.
    const RenderMaps maps = mapsFor(s.method, bs.plan);
    PhotonPassOptions pass;
    pass.buildGlobal = maps.global;
    pass.buildCaustic = maps.caustic;
    pass.globalPhotons = maps.global ? s.globalPhotons : 0;
    pass.causticPhotons = maps.caustic ? s.causticPhotons : 0;
    MemoryPlan memory;
    if (!path) {
        memory = planMemory(photonPassMemoryRequest(bs.geometry, bs.buffers, pass), memoryLimits(device->info()));
        requireMemoryFits(memory);
        s.photonBatch = memory.photonBatch;
    }

    // Device memory as observed: the largest buffer, and every buffer made up to the end of
    // the first pass summed as if none were freed (an upper bound of the peak: the scene and
    // eye buffers live throughout, a pass's photon buffers are made and dropped within it).
    uint64_t largest = 0, firstPassBytes = 0;
    bool firstPassDone = false;
    if (device)
        device->setAllocationObserver([&](const std::string&, size_t bytes) {
            largest = std::max<uint64_t>(largest, bytes);
            if (!firstPassDone) firstPassBytes += bytes;
        });
    auto userOnPass = s.onPass;
    s.onPass = [&](uint32_t done, double f) {
        firstPassDone = true;
        userOnPass(done, f);
    };

    const std::string started = utcNow();
    PhotonRenderResult r;
    const double setup = std::chrono::duration<double>(Clock::now() - start).count();
    if (s.passes > 0) {
        try {
            r = path ? renderPathPasses(bs, first, s.passes, options.threads, s.stop, s.onPass)
                     : renderPhotonMapped(*device, bs.scene, bs.geometry, bs.buffers, bs.plan, s);
        } catch (...) {
            if (device) device->setAllocationObserver(nullptr);
            throw;
        }
        out.film = std::move(r.sums);  // (no second copy: a 4K film of 128-bit sums is 531 MB)
        if (resumeFrom) out.film.add(resumeFrom->film);  // integer addition: either order, same bits
        r.film = Film();
        out.passesDone += r.passes;
        out.globalEmitted += r.globalEmitted;
        out.causticEmitted += r.causticEmitted;
        out.globalStored += r.globalStored;
        out.causticStored += r.causticStored;
        out.samples += r.samples;
        out.nonFiniteSamples += r.nonFiniteSamples;
    }
    if (device) device->setAllocationObserver(nullptr);
    if (out.film.width() == 0)  // nothing rendered
        out.film = resumeFrom ? resumeFrom->film : FixedPointFilm(job.width, job.height);

    nlohmann::json run;
    run["started"] = started;
    run["finished"] = utcNow();
    run["passes"] = {first, first + r.passes};
    run["device"] = out.device;
    run["host"] = out.host;
    run["stopped"] = r.stopped;
    nlohmann::json sec;
    sec["load"] = options.loadSeconds;
    sec["setup"] = setup;
    sec["photonPass"] = r.times.photons;
    sec["maps"] = r.times.maps;
    sec["camera"] = r.times.camera;
    sec["eyePaths"] = r.times.eyePaths;
    sec["direct"] = r.times.direct;
    sec["caustic"] = r.times.caustic;
    sec["indirect"] = r.times.indirect;
    sec["accumulate"] = r.times.accumulate;
    if (path) sec["pathTrace"] = r.times.total;
    sec["render"] = r.times.total;
    sec["total"] = std::chrono::duration<double>(Clock::now() - start).count() + options.loadSeconds;
    run["seconds"] = sec;
    nlohmann::json mem;
    mem["devicePlannedPhotonPassPeakBytes"] = memory.peakBytes();
    mem["deviceLargestBufferBytes"] = largest;
    mem["deviceFirstPassAllocatedBytes"] = firstPassBytes;
    mem["deviceMaxAllocBytes"] = device ? device->info().maxAlloc : 0;
    mem["deviceGlobalMemBytes"] = device ? device->info().globalMem : 0;
    mem["hostMaxRssBytes"] = hostMaxRssBytes();
    run["memory"] = mem;
    runs.push_back(run);
    out.accounting["runs"] = runs;
    // The totals over the runs: what this shard cost.
    nlohmann::json total = nlohmann::json::object();
    uint64_t rss = 0, peak = 0;
    for (const auto& x : runs) {
        for (auto it = x["seconds"].begin(); it != x["seconds"].end(); ++it)
            total[it.key()] = total.value(it.key(), 0.0) + it.value().get<double>();
        rss = std::max<uint64_t>(rss, x["memory"]["hostMaxRssBytes"].get<uint64_t>());
        peak = std::max<uint64_t>(peak, x["memory"]["deviceFirstPassAllocatedBytes"].get<uint64_t>());
    }
    out.accounting["seconds"] = total;
    out.accounting["hostMaxRssBytes"] = rss;
    out.accounting["deviceBytesUpperBound"] = peak;
    out.accounting["devicePlannedPhotonPassPeakBytes"] = memory.peakBytes();
    return out;
}

}  // namespace pcl
