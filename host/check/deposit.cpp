// `check --stage deposit`: the deterministic deposit of the twin's slots into the maps, record by
// record (photon_stages.h).
#include <algorithm>
#include <cstring>
#include <vector>

#include "check/on_device.h"
#include "check/photon_compare.h"
#include "check/photon_stages.h"
#include "core/clock.h"
#include "reference/deposit.h"
#include "reference/emit.h"

namespace pcl {

void comparePhotonMaps(const std::vector<PclPhoton>& host, const std::vector<PclPhoton>& dev, PhotonCheckRow& row) {
    row.items += host.size();
    row.hostDeposits += host.size();
    row.deviceDeposits += dev.size();
    const size_t n = std::min(host.size(), dev.size());
    for (size_t i = 0; i < n; ++i) row.byteMismatches += std::memcmp(&host[i], &dev[i], sizeof(PclPhoton)) != 0;
    row.byteMismatches += std::max(host.size(), dev.size()) - n;
}

PhotonCheckReport checkDeposit(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                               const PhotonCheckOptions& options) {
    using namespace photon_check;
    return perPassReport(
        "deposit", geometry, buffers, options,
        [&](const CheckPass& pass, PhotonCheckRow& row, PhotonCheckReport& report) {
            // The twin's slots of every batch of the pass, deposited both ways.
            std::vector<uint32_t> allCounts, volumeCounts;
            std::vector<PclPhoton> allSlots, volumeSlots;
            uint32_t slotsPerPath = 0;
            for (const PclPhotonParams& params : pass.batches) {
                const std::vector<PclPhotonRay> rays = emitPhotonsReference(buffers, pass.first, params);
                const ReferencePhotonBatch host = tracePhotonsReference(buffers, geometry, params, rays);
                slotsPerPath = host.slotsPerPath;
                allCounts.insert(allCounts.end(), host.counts.begin(), host.counts.end());
                allSlots.insert(allSlots.end(), host.slots.begin(), host.slots.end());
                volumeCounts.insert(volumeCounts.end(), host.volumeCounts.begin(), host.volumeCounts.end());
                volumeSlots.insert(volumeSlots.end(), host.volumeSlots.begin(), host.volumeSlots.end());
            }
            // Scenes with media: the volume photons' map, deposited the same way, in the same row.
            if (!volumeCounts.empty()) {
                std::vector<PclPhoton> hostVolume;
                depositPhotonsReference(volumeCounts, volumeSlots, slotsPerPath, hostVolume);
                comparePhotonMaps(hostVolume, depositOnDevice(device, volumeCounts, volumeSlots, slotsPerPath, 0), row);
            }
            if (!allCounts.empty()) {
                auto t = Clock::now();
                std::vector<PclPhoton> hostMap;
                depositPhotonsReference(allCounts, allSlots, slotsPerPath, hostMap);
                report.hostSeconds += since(t);
                t = Clock::now();
                // Once into an exactly sized map, once into one a quarter the size (it must grow).
                std::vector<PclPhoton> exact = depositOnDevice(device, allCounts, allSlots, slotsPerPath, 0);
                uint32_t growths = 0;
                std::vector<PclPhoton> grown = depositOnDevice(device, allCounts, allSlots, slotsPerPath,
                                                               std::max<size_t>(1, hostMap.size() / 4), &growths);
                report.deviceSeconds += since(t);
                comparePhotonMaps(hostMap, exact, row);
                PhotonCheckRow again;
                comparePhotonMaps(hostMap, grown, again);
                row.byteMismatches += again.byteMismatches;
                row.growths = growths;
            }
        });
}

}  // namespace pcl
