#include "pipeline/photon_pass.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>

#include "core/clock.h"
#include "core/error.h"
#include "pipeline/deposit.h"
#include "pipeline/device_scene.h"
#include "pipeline/emit.h"
#include "pipeline/trace_photons.h"
#include "prep/photon_allocation.h"

namespace pcl {
namespace {

void tallyEnds(const std::vector<uint32_t>& ends, PhotonPassKindStats& s) {
    for (uint32_t e : ends) {
        s.bounces += e & 0xFFu;
        switch (e >> 8) {
            case PCL_END_ESCAPED: ++s.escaped; break;
            case PCL_END_ABSORBED: ++s.absorbed; break;
            case PCL_END_MAX_DEPTH: ++s.maxDepth; break;
            case PCL_END_STORED: ++s.stored; break;
            default: break;
        }
    }
}

// One map: every batch of one pass kind through emit → trace → deposit.
// A scene with media also fills `volume` with the pass's volume photons, deposited the same way.
std::vector<PclPhoton> buildMap(Device& device, const DeviceScene& scene, const SceneGeometry& geometry,
                                const SceneBuffers& buffers, const PhotonPassOptions& options, uint32_t passKind,
                                uint32_t photons, PhotonPassStats& stats, PhotonPassKindStats& s,
                                std::vector<PclPhoton>& volume, std::vector<float>* times = nullptr) {
    const std::vector<uint32_t> first = lightFirstPhoton(buffers, photons, passKind);
    const uint32_t total = first.back();  // 0 when no light has power (or no marked cell)
    if (total == 0) return {};
    emittedFlux(buffers, first, passKind, s.emittedFlux);
    const uint64_t passSeed = photonPassSeed(options.seed, options.pass);
    PclPhotonParams params = makePhotonParams(geometry, buffers, passKind, passSeed, options.maxDepth, 0, 0);
    const uint32_t slotsPerPath = photonSlotsPerPath(params);
    const bool media = params.hasMedia != 0;
    const uint32_t batch = std::min(
        total, options.batchSize ? options.batchSize : defaultPhotonBatch(device, slotsPerPath * (media ? 2u : 1u)));
    s.batchSize = batch;

    cl::Buffer lightFirst = device.upload(first, CL_MEM_READ_ONLY, "photon pass: light offsets");
    cl::Buffer rays = device.allocate<PclPhotonRay>(batch, CL_MEM_READ_WRITE, "photon pass: rays");
    cl::Buffer slots =
        device.allocate<PclPhoton>(size_t(batch) * slotsPerPath, CL_MEM_READ_WRITE, "photon pass: slots");
    cl::Buffer counts = device.allocate<uint32_t>(batch, CL_MEM_READ_WRITE, "photon pass: counts");
    cl::Buffer ends = device.allocate<uint32_t>(batch, CL_MEM_READ_WRITE, "photon pass: ends");
    const std::string mapName = passKind == PCL_PASS_CAUSTIC ? "caustic" : "global";
    DevicePhotonMap map = makeDevicePhotonMap(
        device,
        options.initialCapacity ? options.initialCapacity : initialMapCapacity(device.info().maxAlloc, passKind, total),
        "photon pass: " + mapName + " map");
    // Volume photons: slots as the surface ones; placeholders the kernel never touches without media.
    cl::Buffer volumeSlots = device.allocate<PclPhoton>(media ? size_t(batch) * slotsPerPath : 1, CL_MEM_READ_WRITE,
                                                        "photon pass: volume slots");
    cl::Buffer volumeCounts =
        device.allocate<uint32_t>(media ? batch : 1, CL_MEM_READ_WRITE, "photon pass: volume counts");
    DevicePhotonMap volumeMap;
    if (media)
        volumeMap = makeDevicePhotonMap(device,
                                        options.initialCapacity
                                            ? options.initialCapacity
                                            : initialMapCapacity(device.info().maxAlloc, passKind, total),
                                        "photon pass: " + mapName + " volume map");

    for (uint32_t firstPhoton = 0; firstPhoton < total; firstPhoton += batch) {
        params.firstPhoton = firstPhoton;
        params.batchSize = std::min(batch, total - firstPhoton);
        cl::Event emitted = emitPhotons(device, scene, lightFirst, params, rays);
        cl::Event traced = tracePhotons(device, scene, params, rays, slots, counts, ends, volumeSlots, volumeCounts);
        DepositTiming timing;
        depositPhotons(device, counts, slots, params.batchSize, map, &timing);
        if (media) {
            DepositTiming volumeTiming;
            depositPhotons(device, volumeCounts, volumeSlots, params.batchSize, volumeMap, &volumeTiming);
            timing.scanSeconds += volumeTiming.scanSeconds;
            timing.growSeconds += volumeTiming.growSeconds;
            timing.scatterSeconds += volumeTiming.scatterSeconds;
        }
        tallyEnds(device.download<uint32_t>(ends, params.batchSize), s);
        if (times) appendRecordTimes(params, device.download<uint32_t>(counts, params.batchSize), *times);
        const double emitS = Device::elapsedSeconds(emitted), traceS = Device::elapsedSeconds(traced);
        const double depositS = timing.scanSeconds + timing.growSeconds + timing.scatterSeconds;
        stats.emitSeconds += emitS;
        stats.traceSeconds += traceS;
        stats.depositSeconds += depositS;
        stats.longestLaunchSeconds = std::max({stats.longestLaunchSeconds, emitS, traceS, depositS});
        s.emitted += params.batchSize;
        ++s.batches;
    }
    s.deposits = map.count;
    s.growths = map.growths;
    s.capacity = map.capacity;
    if (media) {
        s.volumeDeposits = volumeMap.count;
        volume = device.download<PclPhoton>(volumeMap.photons, volumeMap.count);
    }
    return device.download<PclPhoton>(map.photons, map.count);
}

}  // namespace

size_t initialMapCapacity(size_t maxAlloc, uint32_t passKind, uint32_t paths) {
    const size_t guess = passKind == PCL_PASS_CAUSTIC ? size_t(paths) : size_t(paths) * 2;
    return std::max<size_t>(1, std::min(guess, maxMapRecords(maxAlloc)));
}

std::string PhotonPassStats::summary() const {
    char buf[768];
    auto line = [](const char* name, const PhotonPassKindStats& s) {
        char l[512];
        std::snprintf(
            l, sizeof l,
            "%s: %llu paths in %u batches of %u, %llu records (%u growths); ends: %llu escaped, %llu absorbed, "
            "%llu stored, %llu at max depth; flux %.6g %.6g %.6g W\n",
            name, (unsigned long long)s.emitted, s.batches, s.batchSize, (unsigned long long)s.deposits, s.growths,
            (unsigned long long)s.escaped, (unsigned long long)s.absorbed, (unsigned long long)s.stored,
            (unsigned long long)s.maxDepth, s.emittedFlux[0], s.emittedFlux[1], s.emittedFlux[2]);
        std::string text(l);
        if (s.volumeDeposits > 0)  // scenes with media: the pass's volume map
            text.insert(text.size() - 1, "; " + std::to_string(s.volumeDeposits) + " volume records");
        return text;
    };
    std::snprintf(buf, sizeof buf,
                  "device seconds: emit %.4f, trace %.4f, deposit %.4f; longest launch %.4f; wall %.4f s\n",
                  emitSeconds, traceSeconds, depositSeconds, longestLaunchSeconds, wallSeconds);
    return line("global", global) + line("caustic", caustic) + buf;
}

PhotonMaps runPhotonPass(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                         const PhotonPassOptions& options) {
    if (options.maxDepth < 1 || options.maxDepth > 255)
        throw InternalError("photon pass: maxDepth " + std::to_string(options.maxDepth) + ": expected 1..255");
    const auto start = std::chrono::steady_clock::now();
    PhotonMaps maps;
    DeviceScene scene(device, geometry, buffers);
    if (options.buildGlobal && options.globalPhotons > 0)
        maps.global = buildMap(device, scene, geometry, buffers, options, PCL_PASS_GLOBAL, options.globalPhotons,
                               maps.stats, maps.stats.global, maps.volume);
    if (options.buildCaustic && options.causticPhotons > 0)
        maps.caustic = buildMap(device, scene, geometry, buffers, options, PCL_PASS_CAUSTIC, options.causticPhotons,
                                maps.stats, maps.stats.caustic, maps.volumeCaustic,
                                options.causticTimes ? &maps.causticTimes : nullptr);
    maps.stats.wallSeconds = since(start);
    return maps;
}

}  // namespace pcl
