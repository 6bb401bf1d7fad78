#include "check/maps.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <random>

#include "core/clock.h"
#include "geometry/scene_geometry.h"
#include "pipeline/kdtree.h"
#include "pipeline/photon_pass.h"
#include "pipeline/sort.h"
#include "prep/projection_map.h"
#include "prep/scene_buffers.h"
#include "reference/kdtree.h"
#include "reference/sort.h"

namespace pcl {
namespace {

PhotonMaps scenePhotonMaps(Device& device, const PreparedScene& prepared, const MapCheckOptions& o) {
    PhotonPassOptions p;
    p.globalPhotons = o.photons;
    p.causticPhotons = o.photons;
    p.maxDepth = o.maxDepth;
    p.seed = o.seed;
    return runPhotonPass(device, prepared.geometry, prepared.buffers, p);
}

// One sort both ways: 32-bit keys travel as the low halves of `keys`.
MapCheckRow sortRow(Device& device, const std::string& input, std::vector<uint64_t> keys, int keyBits) {
    MapCheckRow row;
    row.input = input;
    row.items = keys.size();
    row.keyBits = keyBits;
    std::vector<uint32_t> values(keys.size());
    for (size_t i = 0; i < values.size(); ++i) values[i] = uint32_t(i);
    std::vector<uint64_t> twinKeys = keys, devKeys;
    std::vector<uint32_t> twinValues = values, devValues;
    Clock::time_point t = Clock::now();
    if (keyBits == 32) {
        std::vector<uint32_t> k32(keys.begin(), keys.end());
        referenceSortPairs(k32, twinValues, 32);
        twinKeys.assign(k32.begin(), k32.end());
    } else {
        referenceSortPairs(twinKeys, twinValues, 64);
    }
    row.hostSeconds = since(t);
    cl::Buffer vb = device.upload(values, CL_MEM_READ_WRITE, "check sort: values");
    if (keyBits == 32) {
        std::vector<uint32_t> k32(keys.begin(), keys.end());
        cl::Buffer kb = device.upload(k32, CL_MEM_READ_WRITE, "check sort: keys");
        sortPairsOnDevice(device, kb, vb, keys.size(), 32, 0, &row.deviceSeconds);
        k32 = device.download<uint32_t>(kb, keys.size());
        devKeys.assign(k32.begin(), k32.end());
    } else {
        cl::Buffer kb = device.upload(keys, CL_MEM_READ_WRITE, "check sort: keys");
        sortPairsOnDevice(device, kb, vb, keys.size(), 64, 0, &row.deviceSeconds);
        devKeys = device.download<uint64_t>(kb, keys.size());
    }
    devValues = device.download<uint32_t>(vb, keys.size());
    compareSorted(twinKeys, twinValues, devKeys, devValues, row);
    return row;
}

std::vector<uint64_t> syntheticKeys(size_t n, int pattern, int keyBits, uint64_t seed) {
    std::mt19937_64 rng(seed);
    const uint64_t mask = keyBits == 64 ? ~uint64_t(0) : 0xFFFFFFFFull;
    std::vector<uint64_t> k(n);
    switch (pattern) {
        case 0:  // random
            for (uint64_t& x : k) x = rng() & mask;
            break;
        case 1:  // sorted
        case 2:  // reversed
            for (uint64_t& x : k) x = rng() & mask;
            std::sort(k.begin(), k.end());
            if (pattern == 2) std::reverse(k.begin(), k.end());
            break;
        case 3:  // all equal
            std::fill(k.begin(), k.end(), rng() & mask);
            break;
        default: {  // few distinct
            uint64_t pool[5];
            for (uint64_t& x : pool) x = rng() & mask;
            for (uint64_t& x : k) x = pool[rng() % 5];
        }
    }
    return k;
}

void addSyntheticRows(Device& device, const MapCheckOptions& o, MapCheckReport& report) {
    const char* names[] = {"random", "sorted", "reversed", "all equal", "few distinct"};
    for (int bits : {32, 64})
        for (int p = 0; p < 5; ++p)
            report.rows.push_back(sortRow(device, std::string(names[p]) + " " + std::to_string(bits),
                                          syntheticKeys(o.syntheticKeys, p, bits, o.seed * 31 + p + bits), bits));
}

float coord(const PclPhoton& p, uint32_t a) { return a == 0 ? p.x : (a == 1 ? p.y : p.z); }
uint32_t axisOf(const PclPhoton& p) { return (p.packed & PCL_PHOTON_AXIS_MASK) >> PCL_PHOTON_AXIS_SHIFT; }

}  // namespace

void compareSorted(const std::vector<uint64_t>& twinKeys, const std::vector<uint32_t>& twinValues,
                   const std::vector<uint64_t>& deviceKeys, const std::vector<uint32_t>& deviceValues,
                   MapCheckRow& row) {
    const size_t n = std::max(twinKeys.size(), deviceKeys.size());
    for (size_t i = 0; i < n; ++i) {
        if (i >= twinKeys.size() || i >= deviceKeys.size() || twinKeys[i] != deviceKeys[i]) ++row.keyMismatches;
        if (i >= twinValues.size() || i >= deviceValues.size() || twinValues[i] != deviceValues[i])
            ++row.valueMismatches;
    }
}

std::string kdTreeDefect(const std::vector<PclPhoton>& map, const std::vector<PclPhoton>& tree,
                         const std::vector<uint32_t>& index) {
    const size_t n = map.size();
    auto at = [](const std::string& what, size_t h) { return what + " at node " + std::to_string(h); };
    if (tree.size() != n || index.size() != n) return "size differs from the map";
    std::vector<char> seen(n, 0);
    for (size_t h = 0; h < n; ++h) {
        if (index[h] >= n || seen[index[h]]) return at("not a permutation", h);
        seen[index[h]] = 1;
        const PclPhoton& a = map[index[h]];
        const PclPhoton& b = tree[h];
        if (std::memcmp(&a, &b, offsetof(PclPhoton, packed)) != 0 ||
            (a.packed & ~PCL_PHOTON_AXIS_MASK) != (b.packed & ~PCL_PHOTON_AXIS_MASK))
            return at("photon differs from map[index]", h);
        if (axisOf(b) > 2) return at("axis 3", h);
    }
    std::vector<float> lo(3 * n), hi(3 * n);
    for (size_t h = n; h-- > 0;) {
        for (uint32_t a = 0; a < 3; ++a) lo[3 * h + a] = hi[3 * h + a] = coord(tree[h], a);
        for (size_t c : {2 * h + 1, 2 * h + 2})
            if (c < n)
                for (uint32_t a = 0; a < 3; ++a) {
                    lo[3 * h + a] = std::min(lo[3 * h + a], lo[3 * c + a]);
                    hi[3 * h + a] = std::max(hi[3 * h + a], hi[3 * c + a]);
                }
        const float e[3] = {hi[3 * h] - lo[3 * h], hi[3 * h + 1] - lo[3 * h + 1], hi[3 * h + 2] - lo[3 * h + 2]};
        const uint32_t want = e[1] > e[0] ? (e[2] > e[1] ? 2 : 1) : (e[2] > e[0] ? 2 : 0);
        if (axisOf(tree[h]) != want) return at("split axis not the largest extent", h);
    }
    for (size_t h = 1; h < n; ++h)
        for (size_t child = h; child > 0; child = (child - 1) / 2) {
            const size_t parent = (child - 1) / 2;
            const uint32_t a = axisOf(tree[parent]);
            const uint64_t kh = uint64_t(referenceFloatKey(coord(tree[h], a))) << 32 | index[h];
            const uint64_t kp = uint64_t(referenceFloatKey(coord(tree[parent], a))) << 32 | index[parent];
            if (child == 2 * parent + 1 ? kh >= kp : kh <= kp)
                return at("order broken against ancestor " + std::to_string(parent), h);
        }
    return "";
}

void compareKdTrees(const std::vector<PclPhoton>& map, const std::vector<PclPhoton>& twin,
                    const std::vector<uint32_t>& twinIndex, const std::vector<PclPhoton>& device,
                    const std::vector<uint32_t>& deviceIndex, MapCheckRow& row) {
    const size_t n = std::max(twin.size(), device.size());
    for (size_t h = 0; h < n; ++h) {
        if (h >= twin.size() || h >= device.size() || std::memcmp(&twin[h], &device[h], sizeof(PclPhoton)) != 0)
            ++row.byteMismatches;
        if (h >= twinIndex.size() || h >= deviceIndex.size() || twinIndex[h] != deviceIndex[h]) ++row.indexMismatches;
    }
    row.defect = kdTreeDefect(map, device, deviceIndex);
}

MapCheckReport checkSort(Device& device, const MapCheckOptions& options) {
    MapCheckReport report;
    report.stage = "sort";
    addSyntheticRows(device, options, report);
    return report;
}

MapCheckReport checkSort(Device& device, const Scene& scene, const MapCheckOptions& options) {
    return checkSort(device, prepareScene(scene), options);
}

MapCheckReport checkSort(Device& device, const PreparedScene& prepared, const MapCheckOptions& options) {
    MapCheckReport report;
    report.stage = "sort";
    PhotonMaps maps = scenePhotonMaps(device, prepared, options);
    for (const auto& [name, map] :
         {std::pair<const char*, const std::vector<PclPhoton>*>{"global", &maps.global}, {"caustic", &maps.caustic}}) {
        if (map->empty()) continue;
        for (uint32_t a = 0; a < 3; ++a) {
            std::vector<uint64_t> keys(map->size());
            for (size_t i = 0; i < keys.size(); ++i) keys[i] = referenceFloatKey(coord((*map)[i], a));
            report.rows.push_back(sortRow(device, std::string(name) + " " + "xyz"[a] + " keys", std::move(keys), 32));
        }
        std::vector<uint64_t> keys(map->size());
        for (size_t i = 0; i < keys.size(); ++i)
            keys[i] = uint64_t(referenceFloatKey((*map)[i].y)) << 32 | referenceFloatKey((*map)[i].x);
        report.rows.push_back(sortRow(device, std::string(name) + " y:x keys", std::move(keys), 64));
    }
    addSyntheticRows(device, options, report);
    return report;
}

MapCheckReport checkKdTreeBuild(Device& device, const Scene& scene, const MapCheckOptions& options) {
    return checkKdTreeBuild(device, prepareScene(scene), options);
}

MapCheckReport checkKdTreeBuild(Device& device, const PreparedScene& prepared, const MapCheckOptions& options) {
    MapCheckReport report;
    report.stage = "build";
    PhotonMaps maps = scenePhotonMaps(device, prepared, options);
    for (const auto& [name, map] :
         {std::pair<const char*, const std::vector<PclPhoton>*>{"global", &maps.global}, {"caustic", &maps.caustic}}) {
        MapCheckRow row;
        row.input = name;
        row.items = map->size();
        Clock::time_point t = Clock::now();
        ReferenceKdTree twin = referenceBuildKdTree(*map);
        row.hostSeconds = since(t);
        KdTreeTiming timing;
        cl::Buffer in = device.upload(*map, CL_MEM_READ_ONLY, "kd-tree: photons");
        DeviceKdTree dt = buildKdTree(device, in, map->size(), &timing);
        row.deviceSeconds = timing.sortSeconds + timing.otherSeconds;
        row.levels = dt.levels;
        std::vector<PclPhoton> devPhotons = device.download<PclPhoton>(dt.photons, dt.count);
        std::vector<uint32_t> devIndex = device.download<uint32_t>(dt.index, dt.count);
        compareKdTrees(*map, twin.photons, twin.index, devPhotons, devIndex, row);
        report.rows.push_back(std::move(row));
    }
    return report;
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
