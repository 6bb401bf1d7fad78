#include "reference/photon_pass.h"
#include "prep/photon_allocation.h"

#include <algorithm>

#include "reference/deposit.h"
#include "reference/emit.h"
#include "reference/trace_photons.h"

namespace pcl {

PclPhotonParams referencePhotonParams(const SceneBuffers& buffers, const SceneGeometry& geometry, uint64_t passSeed,
                                      uint32_t pass, uint32_t firstPhoton, uint32_t batchSize, uint32_t maxDepth,
                                      bool storeGlobal) {
    PclPhotonParams p{};
    p.seedLo = static_cast<uint32_t>(passSeed);
    p.seedHi = static_cast<uint32_t>(passSeed >> 32);
    p.firstPhoton = firstPhoton;
    p.batchSize = batchSize;
    p.lightCount = static_cast<uint32_t>(buffers.lights.size());
    p.triangleCount = geometry.triangleCount();
    p.maxDepth = std::min(255u, std::max(1u, maxDepth));
    p.pass = pass;
    p.hasMotion = buffers.hasMotion ? 1u : 0u;
    p.storeGlobal = storeGlobal ? 1u : 0u;
    p.rayEpsilon = buffers.rayEpsilon;
    p.hasMedia = buffers.hasMedia ? 1u : 0u;
    return p;
}

std::vector<uint32_t> referenceLightFirstPhoton(const SceneBuffers& buffers, uint32_t pass, uint32_t photons) {
    return allocatePhotons(referenceAllocationWeights(buffers, pass), photons);
}

std::vector<PclPhoton> referencePhotonMap(const SceneBuffers& buffers, const SceneGeometry& geometry,
                                          const ReferencePhotonPassSettings& settings, uint32_t pass,
                                          ReferencePhotonStats* stats, std::vector<uint32_t>* pathCounts,
                                          std::vector<PclPhoton>* volume, std::vector<uint32_t>* volumePathCounts) {
    const uint32_t photons = pass == PCL_PASS_CAUSTIC ? settings.causticPhotons : settings.globalPhotons;
    const std::vector<uint32_t> first = referenceLightFirstPhoton(buffers, pass, photons);
    const uint32_t total = first.back();  // 0 when no light has power (or no marked cells)
    const uint64_t seed = referencePhotonPassSeed(settings.seed, settings.pass);
    std::vector<PclPhoton> map;
    for (uint32_t start = 0; start < total; start += settings.batchSize) {
        const uint32_t n = std::min(settings.batchSize, total - start);
        const PclPhotonParams params =
            referencePhotonParams(buffers, geometry, seed, pass, start, n, settings.maxDepth, settings.storeGlobal);
        const std::vector<PclPhotonRay> rays = emitPhotonsReference(buffers, first, params, settings.threads);
        const ReferencePhotonBatch batch = tracePhotonsReference(buffers, geometry, params, rays, settings.threads);
        depositPhotonsReference(batch.counts, batch.slots, batch.slotsPerPath, map);
        if (volume && params.hasMedia)
            depositPhotonsReference(batch.volumeCounts, batch.volumeSlots, batch.slotsPerPath, *volume);
        if (volumePathCounts && params.hasMedia)
            volumePathCounts->insert(volumePathCounts->end(), batch.volumeCounts.begin(), batch.volumeCounts.end());
        if (pathCounts) pathCounts->insert(pathCounts->end(), batch.counts.begin(), batch.counts.end());
        if (stats) {
            stats->paths += n;
            for (uint32_t end : batch.ends) stats->ends[std::min(4u, referenceEndCause(end))]++;
        }
    }
    if (stats) stats->deposits = map.size();
    return map;
}

ReferencePhotonMaps runPhotonPassReference(const SceneBuffers& buffers, const SceneGeometry& geometry,
                                           const ReferencePhotonPassSettings& settings) {
    ReferencePhotonMaps maps;
    if (settings.globalPhotons > 0)
        maps.global =
            referencePhotonMap(buffers, geometry, settings, PCL_PASS_GLOBAL, &maps.globalStats, nullptr, &maps.volume);
    if (settings.causticPhotons > 0) {
        std::vector<uint32_t> counts;
        maps.caustic = referencePhotonMap(buffers, geometry, settings, PCL_PASS_CAUSTIC, &maps.causticStats,
                                          settings.causticTimes ? &counts : nullptr, &maps.volumeCaustic);
        if (settings.causticTimes)  // counts of every batch in path order: path i is photon i
            appendRecordTimes(referencePhotonParams(buffers, geometry,
                                                    referencePhotonPassSeed(settings.seed, settings.pass),
                                                    PCL_PASS_CAUSTIC, 0, 0, settings.maxDepth),
                              counts, maps.causticTimes);
    }
    return maps;
}

}  // namespace pcl
