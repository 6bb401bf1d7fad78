// `check --stage sort`: the device radix sort against std::stable_sort on the scene's photon
// coordinates and on synthetic keys (maps.h).
#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "check/maps.h"
#include "core/clock.h"
#include "pipeline/sort.h"
#include "reference/sort.h"

namespace pcl {
namespace {

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
    PhotonMaps maps = mapCheckPhotonMaps(device, prepared, options);
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

}  // namespace pcl
