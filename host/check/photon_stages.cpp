#include "check/photon_stages.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "check/on_device.h"
#include "core/clock.h"
#include "core/error.h"
#include "pipeline/deposit.h"
#include "pipeline/emit.h"
#include "pipeline/photon_pass.h"
#include "pipeline/trace_photons.h"
#include "prep/projection_map.h"
#include "reference/deposit.h"
#include "reference/emit.h"
#include "reference/photon_pass.h"
#include "reference/trace_photons.h"

namespace pcl {
namespace {

constexpr double kPositionTolerance = 1e-4;   // of max(|p|∞, scene radius)
constexpr double kDirectionTolerance = 1e-4;  // absolute, per component of a unit vector
constexpr double kPowerTolerance = 1e-5;      // of the largest channel

// One pass of the check: its allocation and its photons split over two batches.
struct CheckPass {
    const char* name;
    std::vector<uint32_t> first;
    std::vector<PclPhotonParams> batches;
};

std::vector<CheckPass> checkPasses(const SceneGeometry& geometry, const SceneBuffers& buffers,
                                   const PhotonCheckOptions& o) {
    std::vector<CheckPass> passes;
    const uint64_t seed = referencePhotonPassSeed(o.seed, 0);
    for (uint32_t pass : {PCL_PASS_GLOBAL, PCL_PASS_CAUSTIC}) {
        CheckPass p{
            pass == PCL_PASS_GLOBAL ? "global" : "caustic", referenceLightFirstPhoton(buffers, pass, o.photons), {}};
        const uint32_t total = p.first.back();
        const uint32_t half = total / 2;
        for (auto [start, n] : {std::pair<uint32_t, uint32_t>{0, half}, {half, total - half}})
            if (n > 0) p.batches.push_back(referencePhotonParams(buffers, geometry, seed, pass, start, n, o.maxDepth));
        passes.push_back(std::move(p));
    }
    return passes;
}

Vec3 originOf(const PclPhotonRay& r) { return {r.ox, r.oy, r.oz}; }
Vec3 directionOf(const PclPhotonRay& r) { return {r.dx, r.dy, r.dz}; }
float maxAbs(Vec3 v) { return std::max(std::fabs(v.x), std::max(std::fabs(v.y), std::fabs(v.z))); }

double positionError(Vec3 a, Vec3 b, float sceneRadius) {
    return maxAbs(a - b) / std::max(std::max(maxAbs(a), sceneRadius), 1e-30f);
}

// Decoded channels within one mantissa step of the larger exponent byte.
bool rgbeClose(uint32_t a, uint32_t b) {
    if (a == b) return true;
    const int E = int(std::max(a >> 24, b >> 24));
    const double step = std::ldexp(1.0, E - 136);
    const Vec3 da = referenceDecodeRgbe(a), db = referenceDecodeRgbe(b);
    return maxAbs(da - db) <= step * (1.0 + 1e-6);
}

bool recordsAgree(const PclPhoton& a, const PclPhoton& b, float radius) {
    return positionError({a.x, a.y, a.z}, {b.x, b.y, b.z}, radius) <= kPositionTolerance && a.packed == b.packed &&
           rgbeClose(a.rgbe, b.rgbe);
}

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

void comparePhotonRays(const std::vector<PclPhotonRay>& host, const std::vector<PclPhotonRay>& dev, float radius,
                       PhotonCheckRow& row) {
    for (size_t i = 0; i < host.size(); ++i) {
        const PclPhotonRay& h = host[i];
        const PclPhotonRay& d = dev[i];
        row.items++;
        const double eo = positionError(originOf(h), originOf(d), radius);
        const double ed = maxAbs(directionOf(h) - directionOf(d));
        const Vec3 ph(h.power[0], h.power[1], h.power[2]), pd(d.power[0], d.power[1], d.power[2]);
        const double ep = maxAbs(ph - pd) / std::max(maxComponent(ph), 1e-30f);
        row.maxOriginError = std::max(row.maxOriginError, eo);
        row.maxDirectionError = std::max(row.maxDirectionError, ed);
        row.maxPowerError = std::max(row.maxPowerError, ep);
        row.originMismatches += !(eo <= kPositionTolerance) || h.time != d.time;
        row.directionMismatches += !(ed <= kDirectionTolerance);
        row.powerMismatches += !(ep <= kPowerTolerance);
        row.lightMismatches += h.light != d.light;
    }
}

void comparePhotonPaths(const ReferencePhotonBatch& host, const PhotonTraceResult& dev, float radius,
                        PhotonCheckRow& row) {
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
        if (host.counts[i] != dev.counts[i]) {
            row.countMismatches++;
            divergent = true;
        } else {
            bool pos = false, packed = false, rgbe = false;
            for (uint32_t k = 0; k < host.counts[i]; ++k) {
                const PclPhoton& a = host.slots[i * S + k];
                const PclPhoton& b = dev.slots[i * size_t(dev.slotsPerPath) + k];
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
        }
        row.divergent += divergent;
    }
}

void comparePhotonMaps(const std::vector<PclPhoton>& host, const std::vector<PclPhoton>& dev, PhotonCheckRow& row) {
    row.items += host.size();
    row.hostDeposits += host.size();
    row.deviceDeposits += dev.size();
    const size_t n = std::min(host.size(), dev.size());
    for (size_t i = 0; i < n; ++i) row.byteMismatches += std::memcmp(&host[i], &dev[i], sizeof(PclPhoton)) != 0;
    row.byteMismatches += std::max(host.size(), dev.size()) - n;
}

PhotonCheckReport checkPhotonStage(Device& device, const Scene& scene, const std::string& stage,
                                   const PhotonCheckOptions& options) {
    const PreparedScene prepared = prepareScene(scene);
    return checkPhotonStage(device, prepared.geometry, prepared.buffers, stage, options);
}

PhotonCheckReport checkPhotonStage(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                   const std::string& stage, const PhotonCheckOptions& options) {
    if (stage != "emit" && stage != "trace" && stage != "deposit" && stage != "pass")
        throw InputError("check: unknown photon stage '" + stage + "' (expected emit, trace, deposit or pass)");
    PhotonCheckReport report;
    report.stage = stage;
    report.maxDivergentFraction = options.maxDivergentFraction;
    const float radius = buffers.sceneRadius;

    if (stage == "pass") {
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
            std::vector<uint32_t> counts;
            ReferencePhotonStats stats;
            t = Clock::now();
            std::vector<PclPhoton> map = referencePhotonMap(buffers, geometry, twin, pass, &stats, &counts);
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
        }
        return report;
    }

    for (const CheckPass& pass : checkPasses(geometry, buffers, options)) {
        PhotonCheckRow row;
        row.pass = pass.name;
        std::vector<uint32_t> allCounts;
        std::vector<PclPhoton> allSlots;
        uint32_t slotsPerPath = 0;
        for (const PclPhotonParams& params : pass.batches) {
            auto t = Clock::now();
            const std::vector<PclPhotonRay> rays = emitPhotonsReference(buffers, pass.first, params);
            const double emitHost = since(t);
            if (stage == "emit") {
                report.hostSeconds += emitHost;
                t = Clock::now();
                const std::vector<PclPhotonRay> dev = emitOnDevice(device, geometry, buffers, pass.first, params);
                report.deviceSeconds += since(t);
                comparePhotonRays(rays, dev, radius, row);
                continue;
            }
            t = Clock::now();
            const ReferencePhotonBatch host = tracePhotonsReference(buffers, geometry, params, rays);
            const double traceHost = since(t);
            if (stage == "trace") {
                report.hostSeconds += traceHost;
                t = Clock::now();
                const PhotonTraceResult dev = tracePhotonsOnDevice(device, geometry, buffers, rays, params);
                report.deviceSeconds += since(t);
                comparePhotonPaths(host, dev, radius, row);
                continue;
            }
            // deposit: collect the twin's slots of every batch of the pass
            slotsPerPath = host.slotsPerPath;
            allCounts.insert(allCounts.end(), host.counts.begin(), host.counts.end());
            allSlots.insert(allSlots.end(), host.slots.begin(), host.slots.end());
        }
        if (stage == "deposit" && !allCounts.empty()) {
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
        report.rows.push_back(row);
    }
    return report;
}

bool PhotonCheckReport::passed() const {
    for (const PhotonCheckRow& r : rows) {
        if (stage == "emit" && (r.originMismatches || r.directionMismatches || r.powerMismatches || r.lightMismatches))
            return false;
        if (stage == "trace" && r.items > 0 && double(r.divergent) > maxDivergentFraction * double(r.items))
            return false;
        if (stage == "deposit" && r.byteMismatches) return false;
        if (stage == "pass") {
            const double allowed = maxDivergentFraction * double(r.items);
            const double recordGap = std::fabs(double(r.hostDeposits) - double(r.deviceDeposits));
            if (r.countMismatches || double(r.divergent) > allowed || recordGap > allowed * r.slotsPerPath)
                return false;
        }
    }
    return true;
}

std::string PhotonCheckReport::table() const {
    std::string out;
    char line[512];
    if (stage == "emit") {
        std::snprintf(line, sizeof line, "%-8s %9s %9s %9s %9s %9s %11s %11s %11s\n", "pass", "rays",
                      "origin!=", "dir!=", "power!=", "light!=", "max o err", "max d err", "max P err");
        out += line;
        for (const auto& r : rows) {
            std::snprintf(line, sizeof line, "%-8s %9zu %9zu %9zu %9zu %9zu %11.2e %11.2e %11.2e\n", r.pass.c_str(),
                          r.items, r.originMismatches, r.directionMismatches, r.powerMismatches, r.lightMismatches,
                          r.maxOriginError, r.maxDirectionError, r.maxPowerError);
            out += line;
        }
        std::snprintf(line, sizeof line,
                      "tolerances: origin %.0e of max(|o|, scene radius), direction %.0e, power %.0e of max channel; "
                      "light equal; any mismatch fails\n",
                      kPositionTolerance, kDirectionTolerance, kPowerTolerance);
        out += line;
    } else if (stage == "trace") {
        std::snprintf(line, sizeof line, "%-8s %8s %9s %8s %6s %7s %7s %6s %6s %6s %10s %9s %9s  %s\n", "pass", "paths",
                      "divergent", "%", "end!=", "bounce!", "count!=", "pos!=", "bits!=", "rgbe!=", "max p err",
                      "dep twin", "dep dev", "twin ends: escaped/absorbed/max depth/stored");
        out += line;
        for (const auto& r : rows) {
            std::snprintf(line, sizeof line,
                          "%-8s %8zu %9zu %8.4f %6zu %7zu %7zu %6zu %6zu %6zu %10.2e %9zu %9zu  %zu/%zu/%zu/%zu\n",
                          r.pass.c_str(), r.items, r.divergent, r.items ? 100.0 * r.divergent / r.items : 0.0,
                          r.endMismatches, r.bounceMismatches, r.countMismatches, r.positionMismatches,
                          r.packedMismatches, r.rgbeMismatches, r.maxPositionError, r.hostDeposits, r.deviceDeposits,
                          r.ends[PCL_END_ESCAPED], r.ends[PCL_END_ABSORBED], r.ends[PCL_END_MAX_DEPTH],
                          r.ends[PCL_END_STORED]);
            out += line;
        }
        std::snprintf(line, sizeof line,
                      "a path diverges on any difference: end cause, bounces, deposits, a position beyond %.0e "
                      "relative, packed bits, RGBE beyond one mantissa step; fails above %.2f %% per pass\n",
                      kPositionTolerance, 100.0 * maxDivergentFraction);
        out += line;
    } else if (stage == "pass") {
        std::snprintf(line, sizeof line, "%-8s %8s %9s %8s %10s %10s %10s %8s %8s\n", "map", "paths", "divergent", "%",
                      "rec twin", "rec dev", "identical", "batches", "paths!=");
        out += line;
        for (const auto& r : rows) {
            std::snprintf(line, sizeof line, "%-8s %8zu %9zu %8.4f %10zu %10zu %10zu %8zu %8zu\n", r.pass.c_str(),
                          r.items, r.divergent, r.items ? 100.0 * r.divergent / r.items : 0.0, r.hostDeposits,
                          r.deviceDeposits, r.identicalRecords, r.deviceBatches, r.countMismatches);
            out += line;
        }
        std::snprintf(line, sizeof line,
                      "maps aligned path by path; a path diverges when its records differ from the device's as for "
                      "trace; fails above %.2f %% or when the paths emitted differ\n",
                      100.0 * maxDivergentFraction);
        out += line;
    } else {
        std::snprintf(line, sizeof line, "%-8s %10s %10s %10s %8s\n", "pass", "twin", "device", "bytes!=", "growths");
        out += line;
        for (const auto& r : rows) {
            std::snprintf(line, sizeof line, "%-8s %10zu %10zu %10zu %8u\n", r.pass.c_str(), r.hostDeposits,
                          r.deviceDeposits, r.byteMismatches, r.growths);
            out += line;
        }
        out += "bytes!=: records differing in any byte, summed over two device maps (one sized exactly, one a "
               "quarter the size that must grow); any fails\n";
    }
    std::snprintf(line, sizeof line, "twin %.3f s, device %.3f s (incl. upload/download)\n", hostSeconds,
                  deviceSeconds);
    out += line;
    return out;
}

}  // namespace pcl
