// What the sort and build checks share (sort.cpp, build.cpp): the scene's maps from one device
// photon pass, and their report.
#include "check/maps.h"

#include <cstdio>
#include <string>

#include "pipeline/photon_pass.h"

namespace pcl {

PhotonMaps mapCheckPhotonMaps(Device& device, const PreparedScene& prepared, const MapCheckOptions& o) {
    PhotonPassOptions p;
    p.globalPhotons = o.photons;
    p.causticPhotons = o.photons;
    p.maxDepth = o.maxDepth;
    p.seed = o.seed;
    return runPhotonPass(device, prepared.geometry, prepared.buffers, p);
}

bool MapCheckReport::passed() const {
    for (const MapCheckRow& r : rows)
        if (r.keyMismatches || r.valueMismatches || r.byteMismatches || r.indexMismatches || !r.defect.empty())
            return false;
    return true;
}

std::string MapCheckReport::table() const {
    std::string out;
    char line[512];
    if (stage == "sort") {
        std::snprintf(line, sizeof line, "%-18s %5s %9s %9s %9s %10s %10s %10s\n", "keys", "bits", "pairs",
                      "key!=", "value!=", "dev s", "twin s", "dev/twin");
        out += line;
        for (const MapCheckRow& r : rows) {
            std::snprintf(line, sizeof line, "%-18s %5d %9zu %9zu %9zu %10.4f %10.4f %10.2f\n", r.input.c_str(),
                          r.keyBits, r.items, r.keyMismatches, r.valueMismatches, r.deviceSeconds, r.hostSeconds,
                          r.hostSeconds > 0 ? r.deviceSeconds / r.hostSeconds : 0.0);
            out += line;
        }
        out += "device radix sort vs std::stable_sort: keys and values must be equal at every position "
               "(stable: equal keys keep input order); any difference fails\n";
    } else {
        std::snprintf(line, sizeof line, "%-8s %9s %7s %9s %9s %10s %10s  %s\n", "map", "photons", "levels",
                      "bytes!=", "index!=", "dev s", "twin s", "device tree");
        out += line;
        for (const MapCheckRow& r : rows) {
            std::snprintf(line, sizeof line, "%-8s %9zu %7u %9zu %9zu %10.4f %10.4f  %s\n", r.input.c_str(), r.items,
                          r.levels, r.byteMismatches, r.indexMismatches, r.deviceSeconds, r.hostSeconds,
                          r.defect.empty() ? "valid" : r.defect.c_str());
            out += line;
        }
        out += "device kd-tree vs twin: nodes equal byte for byte (axis bits included) and the same heap -> photon "
               "permutation; the device tree valid (left-balanced heap, largest-extent axis, (key, index) order); "
               "any difference fails\n";
    }
    std::snprintf(line, sizeof line, "%s: %s\n", stage.c_str(), passed() ? "PASSED" : "FAILED");
    out += line;
    return out;
}

}  // namespace pcl
