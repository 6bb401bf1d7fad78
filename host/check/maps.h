// `photoncl check SCENE --stage sort|build` for the photon-map structures: each device stage
// against its CPU twin on the same inputs.
//
//   sort   the device radix sort (pipeline/sort) against std::stable_sort (reference/sort) on
//          keys from the scene's photon maps (the flipped x, y, z coordinates as 32-bit keys;
//          (flipped y << 32 | flipped x) as 64-bit keys) and on synthetic keys (random, sorted,
//          reversed, all equal, few distinct; 32 and 64 bits): keys and values equal bit for bit
//          or the check fails.
//   build  the device kd-tree (pipeline/kdtree) against the twin's (reference/kdtree) on the
//          scene's global and caustic maps from one device photon pass: identical bytes
//          (photons with axis bits, heap → photon permutation), and the device tree checked
//          against the definition (a permutation of the map; each node's axis the largest
//          extent of its subtree's box, ties x, y, z; every left-subtree photon below and every
//          right-subtree photon above the node on its axis by (coordinate key, photon index)).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "pipeline/photon_pass.h"
#include "prep/prepared_scene.h"
#include "scene/scene.h"
#include "shared/types.h"

namespace pcl {

struct MapCheckOptions {
    uint32_t photons = 100000;  // paths per map (global and caustic) of the photon pass
    uint32_t maxDepth = 16;
    uint64_t seed = 1;
    size_t syntheticKeys = 1000000;  // sort: pairs per synthetic pattern
};

struct MapCheckRow {
    std::string input;                               // "global", "caustic", "x keys", "random 64", ...
    size_t items = 0;                                // pairs sorted, or photons in the tree
    int keyBits = 0;                                 // sort
    size_t keyMismatches = 0, valueMismatches = 0;   // sort: positions differing
    size_t byteMismatches = 0, indexMismatches = 0;  // build: nodes differing in any byte / index
    std::string defect;                              // build: first broken tree property of the device tree, "" if none
    uint32_t levels = 0;                             // build: device levels
    double deviceSeconds = 0.0, hostSeconds = 0.0;
};

struct MapCheckReport {
    std::string stage;  // "sort" or "build"
    std::vector<MapCheckRow> rows;
    bool passed() const;        // every row without a mismatch or defect
    std::string table() const;  // printable, one line per input, then the rule
};

// Sort on keys from the scene's maps and on synthetic keys (see above).
MapCheckReport checkSort(Device& device, const Scene& scene, const MapCheckOptions& options = {});
// Sort on synthetic keys only (no scene).
MapCheckReport checkSort(Device& device, const MapCheckOptions& options = {});
// The kd-tree build on the scene's global and caustic maps.
MapCheckReport checkKdTreeBuild(Device& device, const Scene& scene, const MapCheckOptions& options = {});
// The same two on a prepared scene.
MapCheckReport checkSort(Device& device, const PreparedScene& prepared, const MapCheckOptions& options = {});
MapCheckReport checkKdTreeBuild(Device& device, const PreparedScene& prepared, const MapCheckOptions& options = {});

// The scene's global and caustic maps from one device photon pass (both checks' input).
PhotonMaps mapCheckPhotonMaps(Device& device, const PreparedScene& prepared, const MapCheckOptions& options);

// The comparisons, added into `row` (tests feed them broken results).
void compareSorted(const std::vector<uint64_t>& twinKeys, const std::vector<uint32_t>& twinValues,
                   const std::vector<uint64_t>& deviceKeys, const std::vector<uint32_t>& deviceValues,
                   MapCheckRow& row);
void compareKdTrees(const std::vector<PclPhoton>& map, const std::vector<PclPhoton>& twin,
                    const std::vector<uint32_t>& twinIndex, const std::vector<PclPhoton>& device,
                    const std::vector<uint32_t>& deviceIndex, MapCheckRow& row);
// "" when `tree`/`index` is a valid left-balanced kd-tree of `map`, else the first defect.
std::string kdTreeDefect(const std::vector<PclPhoton>& map, const std::vector<PclPhoton>& tree,
                         const std::vector<uint32_t>& index);

}  // namespace pcl
