#include "batch/shard_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "pipeline/memory_plan.h"
#include "pipeline/photon_pass.h"
#include "render/path_render.h"

namespace pcl {
namespace {

// Host bytes per pixel while a shard renders: the render's FixedPointFilm sums (4 × __int128,
// 64) and the pass's Film (4 doubles, 32) live together (at the end the pass film is freed
// before the sums are copied to doubles), plus 16 of slack (allocator, chunk read-backs). A 4K
// direct shard peaked at 1267 MiB against 1299 predicted (with 64-bit sums: 892 against 1020).
constexpr double kHostBytesPerPixel = 64 + 32 + 16;

std::string mib(double bytes) {
    char b[32];
    std::snprintf(b, sizeof b, "%.1f MiB", bytes / (1024.0 * 1024.0));
    return b;
}

std::string hms(double s) {
    char b[48];
    if (s >= 3600) std::snprintf(b, sizeof b, "%dh%02dm", int(s / 3600), int(std::fmod(s, 3600) / 60));
    else if (s >= 60) std::snprintf(b, sizeof b, "%dm%02ds", int(s / 60), int(std::fmod(s, 60)));
    else std::snprintf(b, sizeof b, "%.1fs", s);
    return b;
}

// Device bytes the eye stages allocate per eye sample of a chunk, all counted as live at once
// (an upper bound; labels as Device::allocate reports them, measured on cornell-spheres): camera
// ray 48, eye hit 112, three radiance parts 48, the estimates' query and result records 3 × 32,
// the kNN's indices and distances 8 per neighbour, and for final gathering per gather ray the
// query 32, the gathered ray 32, the precomputed-irradiance lookup 16 and its chosen point 4.
uint64_t eyeBytesPerSample(const PhotonRenderSettings& s) {
    const bool fg = s.method == RenderMethod::FinalGather;
    return 48 + 112 + 3 * 16 + 3 * 32 + 8ull * std::max(s.globalK, s.causticK) + (fg ? 84ull * s.gatherRays : 0ull);
}

void planShards(const BatchJob& job, BatchPlanEstimate& e) {
    for (uint32_t i = 0; i < job.shards; ++i) {
        ShardEstimate se;
        se.index = i;
        se.range = shardPasses(job, i);
        se.seconds = e.calibrated ? e.secondsPerPass * se.range.count() : 0.0;
        e.shards.push_back(se);
    }
}

// The path tracer: no device; the host holds the scene, the BVH and the films. Calibrated by
// one sample per pixel (and the light tracer's pass where the scene needs it) at no more than 65 536 pixels, twice, the second timed, scaled by pixels.
BatchPlanEstimate estimatePathTracer(const BatchScene& bs, bool calibrate, int threads) {
    BatchPlanEstimate e;
    e.device = kPathTracerDevice;
    const size_t pixels = size_t(bs.job.width) * bs.job.height;
    e.hostBytes = uint64_t(kHostBytesPerPixel * pixels) + (200ull << 20);
    if (calibrate) {
        const double shrink = std::min(1.0, std::sqrt(65536.0 / double(pixels)));
        Scene small = bs.scene;
        small.camera.width = std::max(1, int(std::lround(bs.job.width * shrink)));
        small.camera.height = std::max(1, int(std::lround(bs.job.height * shrink)));
        e.calibrationWidth = small.camera.width;
        e.calibrationHeight = small.camera.height;
        // The shards' own loop (render/path_render.h), so a scene that needs the light tracer
        // pays for its pass too.
        PathRenderSettings pt;
        pt.seed = bs.settings.seed;
        pt.samples = 1;
        pt.threads = threads;
        double seconds = 0.0;
        for (int i = 0; i < 2; ++i) seconds = renderPathTraced(small, bs.geometry, pt).seconds;
        const size_t smallPixels = size_t(small.camera.width) * small.camera.height;
        e.eyeSecondsPerPass = seconds * double(pixels) / double(smallPixels);
        e.secondsPerPass = e.eyeSecondsPerPass;
        e.calibrationRssBytes = hostMaxRssBytes();
        e.hostBytes = e.calibrationRssBytes +
                      uint64_t(kHostBytesPerPixel * double(pixels - std::min(pixels, smallPixels)));
        e.calibrated = true;
    }
    planShards(bs.job, e);
    return e;
}

}  // namespace

BatchPlanEstimate estimateBatch(const BatchScene& bs, const DeviceInfo& info, Device* device, bool calibrate,
                                int threads) {
    BatchPlanEstimate e;
    e.device = info.name;
    const PhotonRenderSettings& s = bs.settings;
    const BatchJob& job = bs.job;
    if (s.method == RenderMethod::PathTracing) return estimatePathTracer(bs, calibrate, threads);
    const RenderMaps maps = mapsFor(s.method, bs.plan);
    const size_t pixels = size_t(job.width) * job.height;
    const size_t passSamples = pixels * s.strata * s.strata;

    e.eyeChunk = eyeChunkSamples(s, info.maxAlloc, passSamples);  // the renderer's chunk
    e.deviceEyeBytes = uint64_t(e.eyeChunk) * eyeBytesPerSample(s);

    PhotonPassOptions pass;
    pass.buildGlobal = maps.global;
    pass.buildCaustic = maps.caustic;
    pass.globalPhotons = maps.global ? s.globalPhotons : 0;
    pass.causticPhotons = maps.caustic ? s.causticPhotons : 0;
    MemoryRequest req = photonPassMemoryRequest(bs.geometry, bs.buffers, pass);
    req.queries = e.eyeChunk;  // each chunk's eye hits search the maps
    req.k = std::max(s.globalK, s.causticK);
    const MemoryPlan memory = planMemory(req, memoryLimits(info));
    e.devicePhotonPassBytes = memory.peakBytes();
    for (const std::string& p : memory.problems) e.memoryProblems += "  " + p + "\n";
    e.deviceBytes = e.devicePhotonPassBytes + e.deviceEyeBytes;

    // Host without calibration: the per-pixel films and the photon maps read back (24-byte
    // records, about 2 per emitted global path and 1 per caustic path, ×2 for the copies a
    // pass holds).
    e.hostBytes = uint64_t(kHostBytesPerPixel * pixels) +
                  2ull * 24 * (2ull * pass.globalPhotons + pass.causticPhotons) + (200ull << 20);
    // A CPU device's buffers are host memory (PoCL): they add to the process's RSS.
    e.cpuDevice = (info.type & CL_DEVICE_TYPE_CPU) != 0;
    if (e.cpuDevice) e.hostBytes += e.deviceBytes;

    if (calibrate && device) {
        // One pass at no more than 65 536 pixels (same aspect), rendered twice: the first warms
        // the kernel cache, the second is timed.
        const double shrink = std::min(1.0, std::sqrt(65536.0 / double(pixels)));
        Scene small = bs.scene;
        small.camera.width = std::max(1, int(std::lround(job.width * shrink)));
        small.camera.height = std::max(1, int(std::lround(job.height * shrink)));
        e.calibrationWidth = small.camera.width;
        e.calibrationHeight = small.camera.height;
        PhotonRenderSettings c = s;
        c.firstPass = 0;
        c.passes = 1;
        c.seconds = 0;
        c.photonBatch = memory.photonBatch;
        PhotonRenderResult r;
        for (int i = 0; i < 2; ++i) r = renderPhotonMapped(*device, small, bs.geometry, bs.buffers, bs.plan, c);
        const double ratio = double(pixels) / (double(small.camera.width) * small.camera.height);
        e.photonSecondsPerPass = r.times.photons + r.times.maps;
        e.eyeSecondsPerPass = (r.times.camera + r.times.eyePaths + r.times.direct + r.times.caustic + r.times.indirect +
                               r.times.accumulate) *
                              ratio;
        e.secondsPerPass = e.photonSecondsPerPass + e.eyeSecondsPerPass;
        e.calibrationRssBytes = hostMaxRssBytes();
        const size_t smallPixels = size_t(small.camera.width) * small.camera.height;
        e.hostBytes = e.calibrationRssBytes +
                      uint64_t(kHostBytesPerPixel * double(pixels - std::min(pixels, smallPixels)));
        // A CPU device's buffers are host memory: the full-size chunk's eye buffers add to the RSS.
        if (info.type & CL_DEVICE_TYPE_CPU) {
            const size_t smallChunk = std::min(e.eyeChunk, smallPixels * s.strata * s.strata);
            e.hostBytes += uint64_t(e.eyeChunk - smallChunk) * eyeBytesPerSample(s);
        }
        e.calibrated = true;
    }
    planShards(job, e);
    return e;
}

std::string formatBatchPlan(const BatchScene& bs, const BatchPlanEstimate& e) {
    const BatchJob& job = bs.job;
    const PhotonRenderSettings& s = bs.settings;
    const RenderMaps maps = mapsFor(s.method, bs.plan);
    std::ostringstream o;
    o << "job " << job.path << ": " << job.scene << " at " << job.width << "x" << job.height << ", method "
      << job.method << ", " << job.passes << " passes in " << job.shards << " shard(s), seed " << job.seed << "\n";
    if (s.method == RenderMethod::PathTracing)
        o << "per pass: 1 path-traced sample per pixel (CPU reference path tracer)";
    else
        o << "per pass: " << (maps.global ? s.globalPhotons : 0u) << " global + "
          << (maps.caustic ? s.causticPhotons : 0u) << " caustic photons, " << s.strata * s.strata
          << " eye sample(s)/pixel";
    if (s.method == RenderMethod::FinalGather) o << ", " << s.gatherRays << " gather rays";
    o << "\nsettings " << hex64(bs.settingsHash) << ": " << bs.settingsText << "\n";
    o << "scene hash " << hex64(bs.sceneHash) << "\n";
    o << "shard files: " << shardFolder(job) << "/, image " << job.output << ", manifest " << manifestPath(job)
      << "\n\n";
    const bool path = s.method == RenderMethod::PathTracing;
    o << "memory per shard (device " << e.device << "):\n";
    if (path) o << "  device: none (the path tracer runs on the host's cores)\n";
    else
        o << "  device: " << mib(double(e.deviceBytes)) << " = photon pass, maps and searches "
          << mib(double(e.devicePhotonPassBytes)) << " (memory plan) + eye buffers " << mib(double(e.deviceEyeBytes))
          << " (" << e.eyeChunk << " samples per chunk)\n";
    if (!e.memoryProblems.empty()) o << "  does NOT fit this device:\n" << e.memoryProblems;
    o << "  host:   " << mib(double(e.hostBytes))
      << (e.calibrated ? " (the calibration's peak RSS " + mib(double(e.calibrationRssBytes)) +
                             " + 112 bytes per further pixel: sums and pass film" +
                             (path ? std::string(")") : std::string("; on a CPU device + the larger eye chunk)"))
                       : std::string(" (estimate: 112 bytes per pixel, the photon maps read back, 200 MiB runtime") +
                             (!path && e.cpuDevice ? ", + the device's buffers: a CPU device's are host memory)" : ")"))
      << "\n";
    if (e.calibrated && path) {
        char line[256];
        std::snprintf(
            line, sizeof line,
            "time per pass (1 sample per pixel): %.2fs (one warm pass at %dx%d on the host, scaled by pixels)\n",
            e.secondsPerPass, e.calibrationWidth, e.calibrationHeight);
        o << line;
    } else if (e.calibrated) {
        char line[256];
        std::snprintf(line, sizeof line,
                      "time per pass: %.2fs = photon pass + maps %.2fs + eye stages %.2fs (one warm pass at %dx%d on "
                      "this device, eye stages scaled by pixels)\n",
                      e.secondsPerPass, e.photonSecondsPerPass, e.eyeSecondsPerPass, e.calibrationWidth,
                      e.calibrationHeight);
        o << line;
    } else {
        o << "time: not calibrated (--no-calibrate)\n";
    }
    o << "\n  shard  passes              device      host        time\n";
    double total = 0;
    for (const ShardEstimate& se : e.shards) {
        char line[256];
        std::snprintf(line, sizeof line, "  %5u  [%6u, %6u) %4u  %-10s  %-10s  %s\n", se.index, se.range.first,
                      se.range.end, se.range.count(), mib(double(e.deviceBytes)).c_str(),
                      mib(double(e.hostBytes)).c_str(), e.calibrated ? hms(se.seconds).c_str() : "-");
        o << line;
        total += se.seconds;
    }
    if (e.calibrated) o << "  total " << hms(total) << " of device time (" << job.shards << " shard(s))\n";
    return o.str();
}

}  // namespace pcl
