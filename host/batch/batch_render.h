// Rendering one shard of a batch job: the job's scene loaded and turned into buffers and a plan
// once, the settings resolved exactly as `photoncl render` resolves them (resolveRenderSettings,
// then the job's values), and passes [first, end) rendered by renderPhotonMapped with the global
// pass index in every seed, so shards are independent and their fixed-point sums add up to the
// bits of one run (image/fixed_point_film.h).
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include "batch/batch_job.h"
#include "batch/shard_file.h"
#include "core/hash.h"
#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "prep/plan.h"
#include "prep/scene_buffers.h"
#include "render/photon_renderer.h"
#include "scene/scene.h"

namespace pcl {

struct BatchScene {
    BatchJob job;
    Scene scene;  // camera resized to the job's width × height
    SceneGeometry geometry;
    SceneBuffers buffers;
    RenderPlan plan;
    PhotonRenderSettings settings;  // resolved: the render defaults, then the job's values
    std::string settingsText;       // canonical "key=value;..." of every setting that changes pixels
    uint64_t settingsHash = 0;      // FNV-1a of settingsText
    // FNV-1a of the scene file's bytes and of what was loaded from it and its includes: every
    // mesh's positions, normals and indices, the flat materials, primitive info and lights the
    // kernels read, and the camera's parameters. Changing an included glTF's .bin changes it.
    uint64_t sceneHash = 0;
};

// Loads the job's scene and resolves the settings (no device needed: plan and merge use it too).
BatchScene loadBatchScene(const BatchJob& job);

// What one shard run reports besides its sums.
struct ShardRunOptions {
    const std::atomic<bool>* stop = nullptr;  // Ctrl-C: finish the pass, then stop
    std::function<void(uint32_t done, uint32_t total)> onPass;
    bool log = false;
    double loadSeconds = 0;  // loading the scene and opening the device before this shard (manifest)
    int threads = 0;         // path: CPU threads (0: all cores)
};

// Renders passes [range.first + resumeFrom.passesDone, range.end) on `device` and returns the
// shard: the sums of resumeFrom (a partial shard of the same range, or nothing) plus the new
// passes. Fills every header field (hashes, device, photons, seconds by stage, memory).
// The path tracer (method path) runs on the host: `device` may then be null. Its pass p is
// sample p of every pixel (PathTracerSettings::firstSample), rounded to fixed point on its own,
// so its shards merge exactly too (but `render --method path`, which sums samples in doubles,
// is not the same bits: its film is not accumulated in fixed point).
ShardData renderShard(Device* device, const BatchScene& scene, uint32_t index, PassRange range,
                      const ShardData* resumeFrom, const ShardRunOptions& options);

// The device name a path-traced shard records.
constexpr const char* kPathTracerDevice = "ref (CPU reference path tracer)";

// Host peak resident set size of this process so far, bytes (getrusage ru_maxrss).
uint64_t hostMaxRssBytes();

}  // namespace pcl
