#include "batch/batch_render.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <fstream>

#include "core/clock.h"
#include "core/error.h"
#include "pipeline/camera_rays.h"
#include "prep/prepared_scene.h"
#include "render/path_render.h"
#include "render/render_settings.h"
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
    PreparedScene prepared = prepareScene(b.scene, planSettingsFor(job.method));
    b.geometry = std::move(prepared.geometry);
    b.buffers = std::move(prepared.buffers);
    b.plan = std::move(prepared.plan);

    // The settings exactly as `photoncl render` resolves them (render_settings.h): the render
    // defaults for the method, then every value the job gives; its passes are resolved already.
    RenderRequest q;
    q.method = job.method;
    q.seed = job.seed;
    q.filter = job.filter;
    q.visibility = job.visibility;
    q.gatherSource = job.gatherSource;
    q.structure = job.structure;
    q.caustics = job.caustics;
    q.emitterStrata = job.emitterStrata;
    q.alpha = job.alpha;
    q.gatherImportance = job.gatherImportance;
    q.radius = job.radius;
    q.maxRadius = job.maxRadius;
    q.passes = job.passes;
    q.globalPhotons = job.globalPhotons;
    q.causticPhotons = job.causticPhotons;
    q.k = job.k;
    q.causticK = job.causticK;
    q.lightSamples = job.lightSamples;
    q.strata = job.strata;
    q.gatherRays = job.gatherRays;
    b.settings = resolveRenderSettings(q, b.plan, job.width, job.height).settings;
    b.settings.passes = job.passes;
    // The one serialisation of every setting that changes a pixel (the photon batch, the buffer
    // cap and the shard count are left out: they change launch counts, not results).
    b.settingsText = settingsText(b.settings, b.plan, job.width, job.height, job.passes);
    b.settingsHash = settingsHash(b.settingsText);

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

// The path tracer's passes [first, first + count): one sample per pixel each, on the host, each
// rounded to fixed point on its own (render/path_render.h).
PhotonRenderResult renderPathPasses(const BatchScene& bs, uint32_t first, uint32_t count, int threads,
                                    const std::atomic<bool>* stop,
                                    const std::function<void(uint32_t, double)>& onPass) {
    PathRenderSettings pt;
    pt.seed = bs.settings.seed;
    pt.threads = threads;
    pt.firstSample = first;
    pt.samples = count;
    pt.fixedPoint = true;
    pt.stop = stop;
    pt.progress = onPass;
    PathRenderResult p = renderPathTraced(bs.scene, bs.geometry, pt);
    PhotonRenderResult r;
    r.sums = std::move(p.sums);
    r.samples = p.paths;
    r.nonFiniteSamples = p.discarded;
    r.passes = p.samples;
    r.stopped = p.stopped;
    r.times.total = p.seconds;
    return r;
}

}  // namespace

ShardData renderShard(Device* device, const BatchScene& bs, uint32_t index, PassRange range,
                      const ShardData* resumeFrom, const ShardRunOptions& options) {
    const bool path = bs.settings.method == RenderMethod::PathTracing;
    if (!path && !device) throw InputError("batch: method " + bs.job.method + " needs an OpenCL device");
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
    MemoryPlan memory;
    if (!path) {
        memory = planRenderMemory(device->info(), bs.geometry, bs.buffers, s, bs.plan);
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
    const double setup = since(start);
    if (s.passes > 0) {
        try {
            r = path ? renderPathPasses(bs, first, s.passes, options.threads, s.stop, s.onPass)
                     : renderPhotonMapped(*device, bs.scene, bs.geometry, bs.buffers, bs.plan, s);
        } catch (...) {
            if (device) device->setAllocationObserver(nullptr);
            throw;
        }
        out.film = std::move(r.sums);                    // (no second copy: a 4K film of 128-bit sums is 531 MB)
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
    sec["total"] = since(start) + options.loadSeconds;
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
