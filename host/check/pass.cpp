// `check --stage pass`: the whole photon pass in device batches against the twin's pass, the two
// maps aligned path by path (photon_stages.h).
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "check/on_device.h"
#include "check/photon_compare.h"
#include "check/photon_stages.h"
#include "core/clock.h"
#include "pipeline/photon_pass.h"
#include "reference/photon_pass.h"

namespace pcl {
namespace {

using namespace photon_check;

// Aligns the device map with the twin's, path by path (see photon_stages.h, "pass").
void alignMaps(const std::vector<PclPhoton>& twin, const std::vector<uint32_t>& counts,
               const std::vector<PclPhoton>& dev, uint32_t slotsPerPath, float radius, PhotonCheckRow& row) {
    auto pathMatches = [&](size_t t, size_t d, uint32_t c) {
        if (d + c > dev.size()) return false;
        for (uint32_t k = 0; k < c; ++k)
            if (!recordsAgree(twin[t + k], dev[d + k], radius)) return false;
        return true;
    };
    const size_t window = 2 * size_t(slotsPerPath) + 2;
    size_t t = 0, d = 0;
    bool lost = false;  // the previous path diverged: search for this one
    for (size_t i = 0; i < counts.size(); ++i) {
        const uint32_t c = counts[i];
        row.items++;
        if (c == 0) continue;  // nothing to compare (a lost cursor stays lost)
        size_t found = SIZE_MAX;
        if (pathMatches(t, d, c)) {
            found = d;
        } else if (lost) {
            for (size_t dd = d; dd < std::min(dev.size(), d + window) && found == SIZE_MAX; ++dd)
                if (pathMatches(t, dd, c)) found = dd;
        }
        if (found == SIZE_MAX) {
            // The device's version of this path has some other length: the next path is
            // searched within a window from here.
            row.divergent++;
            lost = true;
            t += c;
            continue;
        }
        lost = false;
        for (uint32_t k = 0; k < c; ++k)
            row.identicalRecords += std::memcmp(&twin[t + k], &dev[found + k], sizeof(PclPhoton)) == 0;
        t += c;
        d = found + c;
    }
}

}  // namespace

PhotonCheckReport checkPhotonPass(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                  const PhotonCheckOptions& options) {
    PhotonCheckReport report;
    report.stage = "pass";
    report.maxDivergentFraction = options.maxDivergentFraction;
    const float radius = buffers.sceneRadius;
    ReferencePhotonPassSettings twin;
    twin.seed = options.seed;
    twin.globalPhotons = options.photons;
    twin.causticPhotons = options.photons;
    twin.maxDepth = options.maxDepth;
    PhotonPassOptions dev;
    dev.seed = options.seed;
    dev.globalPhotons = options.photons;
    dev.causticPhotons = options.photons;
    dev.maxDepth = options.maxDepth;
    dev.batchSize = std::max(1u, options.photons / 3 + 7);  // several batches, unlike the twin's one
    auto t = Clock::now();
    PhotonMaps devMaps = runPhotonPass(device, geometry, buffers, dev);
    report.deviceSeconds = since(t);
    for (uint32_t pass : {PCL_PASS_GLOBAL, PCL_PASS_CAUSTIC}) {
        const bool global = pass == PCL_PASS_GLOBAL;
        PhotonCheckRow row;
        row.pass = global ? "global" : "caustic";
        std::vector<uint32_t> counts, volumeCounts;
        std::vector<PclPhoton> volume;
        ReferencePhotonStats stats;
        t = Clock::now();
        std::vector<PclPhoton> map =
            referencePhotonMap(buffers, geometry, twin, pass, &stats, &counts, &volume, &volumeCounts);
        report.hostSeconds += since(t);
        const std::vector<PclPhoton>& devMap = global ? devMaps.global : devMaps.caustic;
        const PhotonPassKindStats& ds = global ? devMaps.stats.global : devMaps.stats.caustic;
        for (int c = 0; c < 5; ++c) row.ends[c] = stats.ends[c];
        row.hostDeposits = map.size();
        row.deviceDeposits = devMap.size();
        row.deviceBatches = ds.batches;
        row.slotsPerPath = options.maxDepth;
        alignMaps(map, counts, devMap, row.slotsPerPath, radius, row);
        row.countMismatches = ds.emitted != stats.paths;  // paths emitted differ: fails
        report.rows.push_back(row);
        if (buffers.hasMedia) {  // the pass's volume map, aligned the same way
            PhotonCheckRow v;
            v.pass = global ? "volume" : "vcaustic";
            const std::vector<PclPhoton>& devVolume = global ? devMaps.volume : devMaps.volumeCaustic;
            v.hostDeposits = volume.size();
            v.deviceDeposits = devVolume.size();
            v.deviceBatches = ds.batches;
            v.slotsPerPath = options.maxDepth;
            alignMaps(volume, volumeCounts, devVolume, v.slotsPerPath, radius, v);
            report.rows.push_back(v);
        }
    }
    return report;
}

}  // namespace pcl
