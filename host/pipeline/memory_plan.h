// The memory plan: before anything is allocated, the bytes of every device
// buffer the pipeline will ask for, predicted from the plan's counts with the same formulas
// the stages use; the batch sizes of the divisible work (photon paths per launch, kNN queries
// per launch) chosen so that every buffer fits under the device's max allocation and every
// phase's buffers together fit under its global memory less headroom; and, for an indivisible
// buffer that cannot fit (a photon map, a kd-tree array, a scene buffer), a clear InputError
// before any work: the buffer, the bytes, the limit, and what to change.
//
// Each planned buffer carries the label its stage passes to Device::allocate ("photon pass:
// slots"), so a test can compare the prediction with the allocations it observes.
//
//   MemoryRequest req = photonPassMemoryRequest(geometry, buffers, passOptions);
//   req.queries = width * height; req.k = 50;                 // if a search follows
//   MemoryPlan plan = planMemory(req, memoryLimits(device.info()));
//   requireMemoryFits(plan);                                    // InputError naming the buffer
//   passOptions.batchSize = plan.photonBatch;                   // the batch the plan chose
//   std::fputs(formatMemoryPlan(plan).c_str(), stderr);
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "pipeline/photon_pass.h"
#include "prep/scene_buffers.h"

namespace pcl {

// What a device allows, from its DeviceInfo (or made up: analyze without a device).
struct MemoryLimits {
    size_t maxAlloc = 0;                       // the largest single buffer (the cap when lower)
    size_t globalMem = 0;                      // bytes of global memory
    cl_device_type type = CL_DEVICE_TYPE_CPU;  // decides the photon batch, sort, kd-tree and hash-grid shapes
    size_t computeUnits = 1;                   // the hash grid's bucketed build sizes its chunk counts by it
    std::string device;                        // its name, for the table
    std::string maxAllocSource;                // describeMaxAlloc(): "64.0 MiB (cap from --max-buffer-mib)"
    bool capped = false;                       // maxAlloc comes from --max-buffer-mib
};
MemoryLimits memoryLimits(const DeviceInfo& info);

// Elements of the scene buffers DeviceScene uploads.
struct SceneBufferCounts {
    size_t nodes = 0, packets = 0, spheres = 0, materials = 0, primInfo = 0, lights = 0, projCells = 0;
    size_t media = 0;      // media in the scene (0: DeviceScene uploads one-element placeholders)
    size_t skyFloats = 1;  // the sky's texels and tables (one float without a sky)
    // Textures (TextureBuffers): floats of texels and triangles with coordinates (0 without
    // textures: one-element placeholders); the per-material descriptors are `materials` long.
    size_t texelFloats = 0, triangleUvs = 0;
    size_t triangleNormals = 0;                   // smooth-shaded scenes: one PclTriangleNormals per triangle (else 0)
    size_t normalMaps = 0, triangleTangents = 0;  // normal-mapped scenes: per material, per triangle (else 0)
};
SceneBufferCounts sceneBufferCounts(const SceneGeometry& geometry, const SceneBuffers& buffers);

struct MemoryRequest {
    SceneBufferCounts scene;
    uint32_t globalPaths = 0, causticPaths = 0;  // photon paths emitted per map; 0: no such map
    uint32_t maxDepth = 64;                      // slots per path
    uint32_t photonBatch = 0;                    // paths per launch; 0: defaultPhotonBatch under the limits
    // A scene with media: each pass also fills volume slots (as many as its slots) and a volume
    // map (initialMapCapacity, as the surface map); the batch is sized for both slot buffers.
    bool media = false;
    // Records in each map once the pass is done; 0: one per emitted path (the least a map of
    // that many photons holds; the map buffer itself starts at initialMapCapacity and grows).
    size_t globalRecords = 0, causticRecords = 0;
    bool kdTree = true;     // a kd-tree built (and packed for the search) per map
    bool hashGrid = false;  // a hash grid built per map
    size_t queries = 0;     // kNN queries searched per map (0: no search planned)
    uint32_t k = 50;        // neighbours per query (the output stride)
    size_t queryBatch = 0;  // queries per launch; 0: knnQueryBatch under the limits
    // The volume estimate (pipeline/volume_estimate): per volume map with records, a phase
    // "<map> volume estimate" holding the map's device copy, its hash grid and the radiance of
    // one launch of volumeQueries eye records (the segments are the eye pass's buffers).
    size_t volumeRecords = 0, volumeCausticRecords = 0;  // photons per volume map; 0: not estimated
    size_t volumeQueries = 0;                            // eye records per volume estimate launch
};

// The request for a photon pass run with these options (paths per map from lightFirstPhoton,
// as runPhotonPass emits them; no search).
MemoryRequest photonPassMemoryRequest(const SceneGeometry& geometry, const SceneBuffers& buffers,
                                      const PhotonPassOptions& options);

struct PlannedBuffer {
    std::string phase;  // "scene", "global photon pass", "global kd-tree", "global search", ...
    std::string what;   // the allocation label the stage uses ("photon pass: slots")
    size_t count = 0;   // elements
    size_t elementBytes = 0;
    size_t bytes = 0;     // max(count, 1) × elementBytes: what Device::allocate asks for
    size_t batches = 0;   // launches the divisible work is split into; 0: indivisible
    size_t perBatch = 0;  // paths or queries per launch (divisible buffers)
    size_t records = 0;   // photon records the buffer scales with (map-sized buffers), for advice
};

struct MemoryPhase {
    std::string name;  // buffers alive together: a phase's own plus "scene" and the structures kept
    size_t bytes = 0;
};

struct MemoryPlan {
    MemoryLimits limits;
    size_t budget = 0;         // globalMem less headroom: what one phase may hold
    uint32_t photonBatch = 0;  // paths per photon-pass launch (PhotonPassOptions::batchSize)
    size_t queryBatch = 0;     // queries per kNN launch
    std::vector<PlannedBuffer> buffers;
    std::vector<MemoryPhase> phases;
    std::vector<std::string> problems;  // why it cannot run as asked; empty: it fits
    bool fits() const { return problems.empty(); }
    size_t peakBytes() const;
    // The planned buffer with this label in this phase (nullptr if none).
    const PlannedBuffer* find(const std::string& phase, const std::string& what) const;
};

// Global memory held back from the budget: a tenth (the driver, the queue, fragmentation).
constexpr double kMemoryHeadroom = 0.10;

// The plan: predicts, chooses batches (halving them while a phase is over the budget), and
// records a problem for every indivisible buffer above maxAlloc and every phase still above the
// budget. Throws nothing.
MemoryPlan planMemory(const MemoryRequest& request, const MemoryLimits& limits);

// InputError listing the plan's problems ("memory plan: the global photon map needs 72.0 MiB
// ... above the device's max allocation 64.0 MiB (cap from --max-buffer-mib); emit at most
// 2796202 global photons or raise --max-buffer-mib to 72"); nothing when it fits.
void requireMemoryFits(const MemoryPlan& plan);

// The table: one row per buffer (phase, label, elements, MiB, batches), the phases' totals, the
// limits and the problems.
std::string formatMemoryPlan(const MemoryPlan& plan);

}  // namespace pcl
