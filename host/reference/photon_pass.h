// The whole photon pass on the CPU (the twin of pipeline/photon_pass): photons allocated to
// lights by power, emitted, traced with Russian roulette and deposited into the global map
// L(S|D)*D and the caustic map LS+D (kernels/README.md). Multi-threaded over photon paths and
// deterministic: the maps depend on the scene, settings and seed only.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "geometry/scene_geometry.h"
#include "prep/scene_buffers.h"
#include "shared/types.h"

namespace pcl {

struct ReferencePhotonPassSettings {
    uint64_t seed = 0;
    uint32_t pass = 0;  // progressive pass index, mixed into the seed
    uint32_t globalPhotons = 100000;
    uint32_t causticPhotons = 0;    // 0: no caustic map; needs projection cells on the lights
    uint32_t maxDepth = 16;         // 1..255
    uint32_t batchSize = 1u << 16;  // paths traced per batch (bounds the slot memory)
    bool storeGlobal = true;
    unsigned threads = 0;       // 0: all cores
    bool causticTimes = false;  // also each caustic record's emission time (ReferencePhotonMaps::causticTimes)
};

struct ReferencePhotonStats {
    uint64_t paths = 0;
    std::array<uint64_t, 5> ends{};  // by PCL_END_* cause
    uint64_t deposits = 0;
};

struct ReferencePhotonMaps {
    std::vector<PclPhoton> global, caustic;
    std::vector<PclPhoton> volume, volumeCaustic;  // scenes with media: the passes' volume photons
    std::vector<float> causticTimes;               // with causticTimes: caustic[i]'s shutter time
    ReferencePhotonStats globalStats, causticStats;
};

// Params of one batch. pass: PCL_PASS_GLOBAL or PCL_PASS_CAUSTIC.
PclPhotonParams referencePhotonParams(const SceneBuffers& buffers, const SceneGeometry& geometry, uint64_t passSeed,
                                      uint32_t pass, uint32_t firstPhoton, uint32_t batchSize, uint32_t maxDepth,
                                      bool storeGlobal = true);

// lightFirstPhoton for `photons` photons of the given pass (largest-remainder allocation).
std::vector<uint32_t> referenceLightFirstPhoton(const SceneBuffers& buffers, uint32_t pass, uint32_t photons);

// One map: emit, trace and deposit `photons` paths of the pass in batches.
// pathCounts, when given, receives every path's deposit count (for checks that align maps by path).
// In a scene with media `volume` receives the pass's volume photons and volumePathCounts their
// count per path.
std::vector<PclPhoton> referencePhotonMap(const SceneBuffers& buffers, const SceneGeometry& geometry,
                                          const ReferencePhotonPassSettings& settings, uint32_t pass,
                                          ReferencePhotonStats* stats = nullptr,
                                          std::vector<uint32_t>* pathCounts = nullptr,
                                          std::vector<PclPhoton>* volume = nullptr,
                                          std::vector<uint32_t>* volumePathCounts = nullptr);

ReferencePhotonMaps runPhotonPassReference(const SceneBuffers& buffers, const SceneGeometry& geometry,
                                           const ReferencePhotonPassSettings& settings);

}  // namespace pcl
