// `photoncl batch plan`: the shards' pass ranges and what each is
// expected to cost, so a user can size a farm before rendering.
//   device memory: the memory plan's peak for one photon pass with its maps and searches
//     (pipeline/memory_plan.h, the same formulas the stages allocate by) plus the renderer's eye
//     buffers per chunk of samples (camera rays, eye hits, radiance parts, estimate queries,
//     kNN results, and per gather ray 84 bytes: query, gathered ray, lookup, chosen point), all
//     counted as live together (an upper bound);
//   host memory: measured when calibrated (the calibration's peak RSS, plus 112 bytes per extra
//     pixel: the render's 128-bit fixed-point sums 64, the pass's film 32, 16 slack;
//     on a CPU device, whose buffers are host memory, plus the eye buffers of the larger chunk);
//     otherwise the same per-pixel bytes plus the photon maps held on the host;
//   time: calibrated by rendering one pass of the job (its photons, a smaller image: at most
//     65 536 pixels, same aspect) twice on the device and taking the second (warm kernel
//     cache); per pass = photon pass + maps + the eye stages scaled by the pixel ratio.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "batch/batch_render.h"
#include "device/device.h"

namespace pcl {

struct ShardEstimate {
    uint32_t index = 0;
    PassRange range;
    double seconds = 0;  // 0: not calibrated
};

struct BatchPlanEstimate {
    size_t eyeChunk = 0;                 // eye samples per chunk (as the renderer chooses)
    uint64_t devicePhotonPassBytes = 0;  // memory plan peak: photon pass, maps, searches
    uint64_t deviceEyeBytes = 0;         // eye buffers of one chunk
    uint64_t deviceBytes = 0;            // the sum: expected device peak per shard
    bool cpuDevice = false;              // its buffers are host memory (counted in hostBytes)
    uint64_t hostBytes = 0;              // expected host peak RSS per shard
    std::string memoryProblems;          // the memory plan's, when it does not fit ("" fits)
    bool calibrated = false;
    int calibrationWidth = 0, calibrationHeight = 0;
    double photonSecondsPerPass = 0;  // photon pass + maps (independent of the image size)
    double eyeSecondsPerPass = 0;     // eye stages at the job's size (scaled)
    double secondsPerPass = 0;
    uint64_t calibrationRssBytes = 0;
    std::string device;
    std::vector<ShardEstimate> shards;
};

// Memory from the plan; with `calibrate` also time (renders two one-pass calibrations on
// `device`, or on the host for the path tracer, whose device may be null and info empty).
BatchPlanEstimate estimateBatch(const BatchScene& scene, const DeviceInfo& info, Device* device, bool calibrate,
                                int threads = 0);
// The same, calibrated on `calibrateOn` when it is not null (as before method path existed).
inline BatchPlanEstimate estimateBatch(const BatchScene& scene, const DeviceInfo& info, Device* calibrateOn) {
    return estimateBatch(scene, info, calibrateOn, calibrateOn != nullptr);
}

// The table `batch plan` prints.
std::string formatBatchPlan(const BatchScene& scene, const BatchPlanEstimate& e);

}  // namespace pcl
