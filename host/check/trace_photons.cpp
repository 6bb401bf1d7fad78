// `check --stage trace_photons`: photon tracing from the same emitted rays, path by path
// (photon_stages.h).
#include <algorithm>
#include <vector>

#include "check/on_device.h"
#include "check/photon_compare.h"
#include "check/photon_stages.h"
#include "core/clock.h"
#include "reference/emit.h"

namespace pcl {

void comparePhotonPaths(const ReferencePhotonBatch& host, const PhotonTraceResult& dev, float radius,
                        PhotonCheckRow& row) {
    using namespace photon_check;
    const uint32_t S = host.slotsPerPath;
    for (size_t i = 0; i < host.counts.size(); ++i) {
        row.items++;
        row.ends[std::min(4u, referenceEndCause(host.ends[i]))]++;
        row.hostDeposits += host.counts[i];
        row.deviceDeposits += dev.counts[i];
        bool divergent = false;
        if (referenceEndCause(host.ends[i]) != referenceEndCause(dev.ends[i])) {
            row.endMismatches++;
            divergent = true;
        }
        if (referenceEndBounces(host.ends[i]) != referenceEndBounces(dev.ends[i])) {
            row.bounceMismatches++;
            divergent = true;
        }
        // One path's records, surface or volume: the same count, then each record's position,
        // packed direction and flags, and power.
        auto compareRecords = [&](uint32_t hostCount, uint32_t devCount, const std::vector<PclPhoton>& hostSlots,
                                  const std::vector<PclPhoton>& devSlots) {
            if (hostCount != devCount) {
                row.countMismatches++;
                divergent = true;
                return;
            }
            bool pos = false, packed = false, rgbe = false;
            for (uint32_t k = 0; k < hostCount; ++k) {
                const PclPhoton& a = hostSlots[i * S + k];
                const PclPhoton& b = devSlots[i * size_t(dev.slotsPerPath) + k];
                const double e = positionError({a.x, a.y, a.z}, {b.x, b.y, b.z}, radius);
                row.maxPositionError = std::max(row.maxPositionError, e);
                pos |= !(e <= kPositionTolerance);
                packed |= a.packed != b.packed;
                rgbe |= !rgbeClose(a.rgbe, b.rgbe);
            }
            row.positionMismatches += pos;
            row.packedMismatches += packed;
            row.rgbeMismatches += rgbe;
            divergent |= pos || packed || rgbe;
        };
        compareRecords(host.counts[i], dev.counts[i], host.slots, dev.slots);
        // Volume photons (scenes with media): the same count and records, path by path.
        if (!host.volumeCounts.empty()) {
            row.hostDeposits += host.volumeCounts[i];
            row.deviceDeposits += dev.volumeCounts[i];
            compareRecords(host.volumeCounts[i], dev.volumeCounts[i], host.volumeSlots, dev.volumeSlots);
        }
        row.divergent += divergent;
    }
}

PhotonCheckReport checkTracePhotons(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                    const PhotonCheckOptions& options) {
    using namespace photon_check;
    return perPassReport(
        "trace", geometry, buffers, options,
        [&](const CheckPass& pass, PhotonCheckRow& row, PhotonCheckReport& report) {
            for (const PclPhotonParams& params : pass.batches) {
                const std::vector<PclPhotonRay> rays = emitPhotonsReference(buffers, pass.first, params);
                auto t = Clock::now();
                const ReferencePhotonBatch host = tracePhotonsReference(buffers, geometry, params, rays);
                report.hostSeconds += since(t);
                t = Clock::now();
                const PhotonTraceResult dev = tracePhotonsOnDevice(device, geometry, buffers, rays, params);
                report.deviceSeconds += since(t);
                comparePhotonPaths(host, dev, buffers.sceneRadius, row);
            }
        });
}

}  // namespace pcl
