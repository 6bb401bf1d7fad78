// The photon pass (Jensen 2001, ch. 5; stages emit, trace_photons and deposit of kernels/README.md): for each pass kind the scene
// needs (global, caustic) and each batch of photons: emit → trace → deposit, on the device.
// Returns the two maps and what happened on the way.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "pipeline/trace_photons.h"
#include "prep/scene_buffers.h"
#include "shared/types.h"

namespace pcl {

struct PhotonPassOptions {
    uint32_t globalPhotons = 100000;   // paths emitted for the global map
    uint32_t causticPhotons = 100000;  // paths emitted for the caustic map (through projection maps)
    uint32_t maxDepth = 64;            // bounces per path (1..255)
    uint32_t batchSize = 0;            // paths per launch; 0: defaultPhotonBatch()
    uint64_t seed = 1;                 // render seed
    uint32_t pass = 0;                 // progressive pass index (mixed into the seed)
    bool buildGlobal = true;
    bool buildCaustic = true;
    size_t initialCapacity = 0;  // records per map before growth; 0: an estimate
    bool causticTimes = false;   // also each caustic record's emission time (PhotonMaps::causticTimes)
};

// Per map (pass kind).
struct PhotonPassKindStats {
    uint64_t emitted = 0;                                          // paths emitted
    uint64_t escaped = 0, absorbed = 0, maxDepth = 0, stored = 0;  // ends by PCL_END_* cause (stored:
                                                                   // caustic paths ended at a hit they deposited at)
    uint64_t bounces = 0;                                          // Σ bounce field of ends: segments traced
    uint64_t deposits = 0;                                         // records in the map
    uint64_t volumeDeposits = 0;                                   // records in the volume map (media)
    double emittedFlux[3] = {0, 0, 0};  // Σ flux of the emitted photons (computed as emit does)
    uint32_t batches = 0;
    uint32_t batchSize = 0;  // paths per batch (launch)
    uint32_t growths = 0;    // map buffer growth events
    size_t capacity = 0;     // final buffer capacity (records)
};

struct PhotonPassStats {
    PhotonPassKindStats global, caustic;
    double emitSeconds = 0, traceSeconds = 0, depositSeconds = 0;  // device time (event profiling)
    double wallSeconds = 0;
    // The longest single launch (emit, trace, or a batch's deposit launches together): batches
    // are sized so it stays far below a GPU watchdog's limit (< 0.5 s a launch at 10M photons).
    double longestLaunchSeconds = 0;
    std::string summary() const;  // a few lines for logs
};

struct PhotonMaps {
    std::vector<PclPhoton> global, caustic;
    // Scenes with media: the volume photons of the global pass (L(S|D|V)*V) and of the caustic
    // pass (the volume caustics L S+ V, Jensen & Christensen 1998), each its own map.
    std::vector<PclPhoton> volume, volumeCaustic;
    // With PhotonPassOptions::causticTimes: caustic[i]'s shutter time (prep/photon_allocation.h,
    // photonEmissionTime), for connections in scenes that move; empty otherwise.
    std::vector<float> causticTimes;
    PhotonPassStats stats;
};

// Records a map buffer starts with (PhotonPassOptions::initialCapacity 0): a caustic path
// deposits about once (more only through mixed surfaces), a global one about 1/(1 - albedo)
// times, so `paths` or 2 × `paths` records, never more than one buffer of maxAlloc bytes holds
// (growth covers a wrong guess, up to that limit). The memory plan predicts the same.
size_t initialMapCapacity(size_t maxAlloc, uint32_t passKind, uint32_t paths);

// Runs the photon pass. The caustic pass uses buffers.projCells / light.projFirst/projCount;
// lights with no marked cell emit no caustic photons, and a scene without any gets no caustic map.
PhotonMaps runPhotonPass(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                         const PhotonPassOptions& options);

}  // namespace pcl
