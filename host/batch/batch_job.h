// A batch job: one render split into shards of passes that any machine can render
// independently (`photoncl batch run JOB --shard I/N`) and that merge into exactly the image one
// run of all the passes gives (`photoncl batch merge JOB`). The job file is JSON (README, "Batch
// renders"); every key is checked, paths are relative to the job file, and settings left out take
// the defaults `photoncl render` uses (resolveRenderSettings, defaultPasses), so a job renders what
// `render` renders.
//
// Files of a job with output "out/cornell.exr":
//   out/cornell.exr, out/cornell.png        the merged image (merge)
//   out/cornell.manifest.json               every shard: passes, device, times, memory (merge)
//   out/cornell.exr.shards/shard-0003-of-0007.pcls   shard 3 of 7 (batch run)
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace pcl {

// Passes [first, end) of the render, global pass indices (the pass index is in every seed).
struct PassRange {
    uint32_t first = 0, end = 0;
    uint32_t count() const { return end - first; }
};

struct BatchJob {
    std::string path;           // the job file as given
    std::string scene;          // scene file, resolved against the job file's folder
    std::string output;         // final EXR, resolved against the job file's folder
    std::string method = "fg";  // fg | direct | progressive | path (the CPU reference path tracer)
    uint32_t shards = 1;        // N
    uint32_t passes = 0;        // P: total passes (resolved: the render default when left out);
                                // path: samples per pixel, one per pass
    uint64_t seed = 0;
    int width = 0, height = 0;  // resolved: the scene camera's when left out (one alone keeps the aspect)
    // Settings; 0 / empty: the render default for the method (resolveRenderSettings).
    uint32_t globalPhotons = 0, causticPhotons = 0, strata = 0, gatherRays = 0, k = 0, causticK = 0, lightSamples = 0,
             gatherImportance = 0;
    float radius = 0.0f, alpha = 2.0f / 3.0f, maxRadius = 0.0f;
    std::string filter = "cone", gatherSource = "precomputed", structure = "kd-tree";
    std::string caustics;    // fg: "connect", "map"; empty: the render default
    int emitterStrata = -1;  // fg: the emitter samples' M (0: off); -1: the render default
    bool visibility = false;
    std::string device = "cpu";  // default for `batch run` (--device overrides)
    uint64_t maxBufferMib = 0;   // 0: no cap
    int threads = 0;             // path: CPU threads (0: all cores); never changes the bits
};

// Reads and checks a job file. Unknown keys, wrong types and values out of range throw
// InputError naming the file, the key, what was found and what was expected. Loads the scene's
// camera to resolve width, height and the default passes.
BatchJob loadBatchJob(const std::string& path);

// Passes of shard i: [i·P/N, (i+1)·P/N) (64-bit products: no overflow).
PassRange shardPasses(const BatchJob& job, uint32_t i);

// "<output>.shards": the folder beside the output holding the shard files.
std::string shardFolder(const BatchJob& job);
// "<output>.shards/shard-0003-of-0007.pcls" for i = 3, N = 7.
std::string shardPath(const BatchJob& job, uint32_t i);
// "<output without extension>.manifest.json".
std::string manifestPath(const BatchJob& job);

}  // namespace pcl
