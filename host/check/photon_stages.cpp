#include "check/photon_stages.h"

#include <cstdio>
#include <string>

#include "check/photon_compare.h"
#include "core/error.h"

namespace pcl {

PhotonCheckReport checkPhotonStage(Device& device, const Scene& scene, const std::string& stage,
                                   const PhotonCheckOptions& options) {
    const PreparedScene prepared = prepareScene(scene);
    return checkPhotonStage(device, prepared.geometry, prepared.buffers, stage, options);
}

PhotonCheckReport checkPhotonStage(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                   const std::string& stage, const PhotonCheckOptions& options) {
    if (stage == "emit") return checkEmit(device, geometry, buffers, options);
    if (stage == "trace") return checkTracePhotons(device, geometry, buffers, options);
    if (stage == "deposit") return checkDeposit(device, geometry, buffers, options);
    if (stage == "pass") return checkPhotonPass(device, geometry, buffers, options);
    throw InputError("check: unknown photon stage '" + stage + "' (expected emit, trace, deposit or pass)");
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
    using namespace photon_check;
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
