// `check --stage build`: the device kd-tree against the twin's, byte for byte, and against the
// definition of a left-balanced kd-tree (maps.h).
#include <algorithm>
#include <string>
#include <vector>

#include "check/maps.h"
#include "core/clock.h"
#include "pipeline/kdtree.h"
#include "reference/kdtree.h"
#include "reference/sort.h"

namespace pcl {
namespace {

float coord(const PclPhoton& p, uint32_t a) { return a == 0 ? p.x : (a == 1 ? p.y : p.z); }
uint32_t axisOf(const PclPhoton& p) { return (p.packed & PCL_PHOTON_AXIS_MASK) >> PCL_PHOTON_AXIS_SHIFT; }

}  // namespace

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

MapCheckReport checkKdTreeBuild(Device& device, const Scene& scene, const MapCheckOptions& options) {
    return checkKdTreeBuild(device, prepareScene(scene), options);
}

MapCheckReport checkKdTreeBuild(Device& device, const PreparedScene& prepared, const MapCheckOptions& options) {
    MapCheckReport report;
    report.stage = "build";
    PhotonMaps maps = mapCheckPhotonMaps(device, prepared, options);
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

}  // namespace pcl
