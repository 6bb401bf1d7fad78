#include "pipeline/memory_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <sstream>

#include "core/error.h"
#include "device/work_group.h"
#include "pipeline/deposit.h"
#include "pipeline/hashgrid.h"
#include "pipeline/kdtree.h"
#include "pipeline/knn.h"
#include "pipeline/sort.h"
#include "pipeline/trace_photons.h"
#include "prep/photon_allocation.h"

namespace pcl {
namespace {

constexpr size_t kMiB = size_t(1) << 20;
constexpr size_t kScanGroup = 256;            // deposit_scan's work-group (pipeline/deposit.cpp)
constexpr size_t kMinBatch = kWorkGroupSize;  // one work-group: the smallest batch the plan shrinks to

size_t ceilDiv(size_t a, size_t b) { return (a + b - 1) / b; }

size_t nextPowerOfTwo(size_t n) {
    size_t p = 1;
    while (p < n) p <<= 1;
    return p;
}

std::string gib(size_t bytes) {
    char buf[48];
    if (bytes >= (size_t(1) << 30)) std::snprintf(buf, sizeof buf, "%.2f GiB", double(bytes) / double(size_t(1) << 30));
    else return formatMiB(bytes);
    return buf;
}

// Builds the buffer list and phase totals for one choice of batches.
class Planner {
public:
    Planner(const MemoryRequest& r, const MemoryLimits& l, MemoryPlan& p) : req(r), lim(l), plan(p) {}

    void build() {
        plan.buffers.clear();
        plan.phases.clear();
        scene();
        const size_t sceneBytes = phaseBytes("scene");
        plan.phases.push_back({"scene", sceneBytes});
        struct Map {
            const char* name;
            uint32_t kind, paths;
            size_t records;
        } maps[2] = {{"global", PCL_PASS_GLOBAL, req.globalPaths,
                      req.globalRecords ? req.globalRecords : req.globalPaths},
                     {"caustic", PCL_PASS_CAUSTIC, req.causticPaths,
                      req.causticRecords ? req.causticRecords : req.causticPaths}};
        for (const Map& m : maps)
            if (m.paths) {
                const std::string phase = std::string(m.name) + " photon pass";
                photonPass(phase, m.name, m.kind, m.paths);
                plan.phases.push_back({phase, sceneBytes + phaseBytes(phase)});
            }
        size_t kept = 0;  // structures built earlier, alive for the search
        for (const Map& m : maps) {
            if (!m.paths || !m.records) continue;
            if (req.kdTree) {
                const std::string phase = std::string(m.name) + " kd-tree";
                kdTree(phase, m.records);
                plan.phases.push_back({phase, sceneBytes + kept + phaseBytes(phase)});
                kept += plan.find(phase, "knn: packed kd-tree")->bytes;
            }
            if (req.hashGrid) {
                const std::string phase = std::string(m.name) + " hash grid";
                hashGrid(phase, m.records);
                plan.phases.push_back({phase, sceneBytes + kept + phaseBytes(phase)});
                for (const char* w : {"hash grid: keys", "hash grid: order", "hash grid: cell starts",
                                      "hash grid: cell ends", "hash grid: points"})
                    kept += plan.find(phase, w)->bytes;
            }
        }
        const std::pair<const char*, size_t> volumeMaps[2] = {{"global", req.volumeRecords},
                                                              {"caustic", req.volumeCausticRecords}};
        for (const auto& [name, records] : volumeMaps)
            if (records && req.volumeQueries) {
                const std::string phase = std::string(name) + " volume estimate";
                volumeEstimate(phase, records);
                plan.phases.push_back({phase, sceneBytes + kept + phaseBytes(phase)});
            }
        if (req.queries)
            for (const Map& m : maps) {
                if (!m.paths || !m.records) continue;
                const std::string phase = std::string(m.name) + " search";
                search(phase);
                plan.phases.push_back({phase, sceneBytes + kept + phaseBytes(phase)});
            }
    }

private:
    void add(const std::string& phase, const std::string& what, size_t count, size_t elementBytes, size_t batches = 0,
             size_t perBatch = 0, size_t records = 0) {
        PlannedBuffer b;
        b.phase = phase;
        b.what = what;
        b.count = count;
        b.elementBytes = elementBytes;
        b.bytes = std::max<size_t>(count, 1) * elementBytes;
        b.batches = batches;
        b.perBatch = perBatch;
        b.records = records;
        plan.buffers.push_back(b);
    }
    size_t phaseBytes(const std::string& phase) const {
        size_t sum = 0;
        for (const PlannedBuffer& b : plan.buffers)
            if (b.phase == phase) sum += b.bytes;
        return sum;
    }

    // DeviceScene: the BVH (DeviceGeometry) and the shading buffers, uploaded once.
    void scene() {
        const SceneBufferCounts& s = req.scene;
        add("scene", "scene: BVH nodes", s.nodes, sizeof(PclBvhNode));
        add("scene", "scene: triangle packets", s.packets, sizeof(PclTriPacket));
        add("scene", "scene: spheres", s.spheres, sizeof(PclSphere));
        add("scene", "scene: materials", s.materials, sizeof(PclMaterial));
        add("scene", "scene: primitive info", s.primInfo, sizeof(PclPrimInfo));
        add("scene", "scene: lights", s.lights, sizeof(PclLight));
        add("scene", "scene: projection cells", s.projCells, sizeof(uint32_t));
        add("scene", "scene: media", s.media, sizeof(PclMedium));
        add("scene", "scene: primitive media", s.media ? s.primInfo : 0, sizeof(PclPrimMedium));
        add("scene", "scene: light media", s.media ? s.lights : 0, sizeof(int32_t));
        add("scene", "scene: environment", s.skyFloats, sizeof(float));
        add("scene", "scene: material textures", s.materials, sizeof(PclMaterialTextures));
        add("scene", "scene: texels", s.texelFloats, sizeof(float));
        add("scene", "scene: triangle texture coordinates", s.triangleUvs, sizeof(PclTriangleUv));
        add("scene", "scene: triangle normals", s.triangleNormals, sizeof(PclTriangleNormals));
        add("scene", "scene: normal maps", s.normalMaps, sizeof(PclNormalMap));
        add("scene", "scene: triangle tangents", s.triangleTangents, sizeof(PclTriangleTangents));
    }

    // runPhotonPass's buildMap: per batch emit → trace → deposit; the map buffer from
    // initialMapCapacity (growth past it is not predicted: it depends on where paths end).
    void photonPass(const std::string& phase, const char* map, uint32_t kind, uint32_t paths) {
        const size_t batch = std::min<size_t>(paths, plan.photonBatch);
        const size_t batches = ceilDiv(paths, batch);
        const size_t slots = std::max<uint32_t>(req.maxDepth, 1);
        add(phase, "photon pass: light offsets", req.scene.lights + 1, sizeof(uint32_t));
        add(phase, "photon pass: rays", batch, sizeof(PclPhotonRay), batches, batch);
        add(phase, "photon pass: slots", batch * slots, sizeof(PclPhoton), batches, batch);
        add(phase, "photon pass: counts", batch, sizeof(uint32_t), batches, batch);
        add(phase, "photon pass: ends", batch, sizeof(uint32_t), batches, batch);
        add(phase, "photon pass: " + std::string(map) + " map", initialMapCapacity(lim.maxAlloc, kind, paths),
            sizeof(PclPhoton));
        // Volume photons: placeholders of one element without media.
        add(phase, "photon pass: volume slots", req.media ? batch * slots : 0, sizeof(PclPhoton), batches, batch);
        add(phase, "photon pass: volume counts", req.media ? batch : 0, sizeof(uint32_t), batches, batch);
        if (req.media)
            add(phase, "photon pass: " + std::string(map) + " volume map",
                initialMapCapacity(lim.maxAlloc, kind, paths), sizeof(PclPhoton));
        const size_t groups = ceilDiv(batch, kScanGroup);
        add(phase, "deposit: offsets", batch, sizeof(uint32_t), batches, batch);
        add(phase, "deposit: group sums", groups, sizeof(uint32_t), batches, batch);
        if (groups > 1) add(phase, "deposit: group offsets", groups, sizeof(uint32_t), batches, batch);
    }

    // The sort workspace sortPairsOnDevice allocates for n pairs (none below 2).
    void sortWorkspace(const std::string& phase, size_t n, int keyBits, size_t records) {
        if (n < 2) return;
        add(phase, keyBits == 64 ? "sort: scratch keys (64-bit)" : "sort: scratch keys (32-bit)", n,
            keyBits == 64 ? 8 : 4, 0, 0, records);
        add(phase, "sort: scratch values", n, sizeof(uint32_t), 0, 0, records);
        add(phase, "sort: tile histogram", sortHistogramEntries(lim.type, n), sizeof(uint32_t), 0, 0, records);
    }

    // buildKdTree of the map on the device, then packKdTree (kept for the search).
    void kdTree(const std::string& phase, size_t n) {
        add(phase, "kd-tree: photons", n, sizeof(PclPhoton), 0, 0, n);
        add(phase, "kd-tree: nodes", n, sizeof(PclPhoton), 0, 0, n);
        add(phase, "kd-tree: node index", n, sizeof(uint32_t), 0, 0, n);
        for (const char* list : {"x", "y", "z", "x (second)", "y (second)", "z (second)"})
            add(phase, std::string("kd-tree: list ") + list, n, 4 * sizeof(uint32_t), 0, 0, n);
        add(phase, "kd-tree: subtree ranges", n, 4 * sizeof(uint32_t), 0, 0, n);
        add(phase, "kd-tree: node axes", n, sizeof(uint8_t), 0, 0, n);
        const size_t counts = kdTreeCountEntries(n, kdTreeFinishSize(lim.type), lim.type);
        if (counts) add(phase, "kd-tree: chunk counts", counts, sizeof(uint32_t), 0, 0, n);
        add(phase, "kd-tree: keys", n, sizeof(uint32_t), 0, 0, n);
        add(phase, "kd-tree: values", n, sizeof(uint32_t), 0, 0, n);
        sortWorkspace(phase, n, 32, n);
        add(phase, "knn: packed kd-tree", knnPackedKdTreeElements(n), 4 * sizeof(float), 0, 0, n);
    }

    // buildHashGrid of the map on the device (table: the power of two ≥ n); `photons` names the
    // map's own upload.
    void hashGrid(const std::string& phase, size_t n, const char* photons = "hash grid: photons") {
        const size_t table = nextPowerOfTwo(std::max<size_t>(n, 1));
        add(phase, photons, n, sizeof(PclPhoton), 0, 0, n);
        add(phase, "hash grid: keys", n, sizeof(uint32_t), 0, 0, n);
        add(phase, "hash grid: order", n, sizeof(uint32_t), 0, 0, n);
        add(phase, "hash grid: cell starts", table, sizeof(uint32_t), 0, 0, n);
        add(phase, "hash grid: cell ends", table, sizeof(uint32_t), 0, 0, n);
        add(phase, "hash grid: points", n, 4 * sizeof(float), 0, 0, n);
        if (n == 0) return;
        if (hashGridBuildFor(lim.type) == HashGridBuild::Sorted) {
            sortWorkspace(phase, n, 32, n);
            return;
        }
        const HashGridBucketShape b = hashGridBucketShape(n, uint32_t(table), lim.computeUnits);
        add(phase, "hash grid: bucket counts", b.buckets * b.chunks, sizeof(uint32_t), 0, 0, n);
        add(phase, "hash grid: bucket keys", n, sizeof(uint32_t), 0, 0, n);
        add(phase, "hash grid: bucket points", n, 4 * sizeof(float), 0, 0, n);
    }

    // buildVolumeMap (the photons and their radii², their hash grid of cell size r, the packed
    // records) and estimateVolumeRadiance.
    void volumeEstimate(const std::string& phase, size_t n) {
        hashGrid(phase, n, "volume estimate: photons");
        add(phase, "volume estimate: radii²", n, sizeof(float), 0, 0, n);
        for (const char* w : {"volume estimate: packed positions", "volume estimate: packed directions",
                              "volume estimate: packed power"})
            add(phase, w, n, 4 * sizeof(float), 0, 0, n);
        add(phase, "volume estimate: radiance", req.volumeQueries, sizeof(PclRadiance));
    }

    // The kNN search in batches of queries (knn.cpp's searchAndDownload).
    void search(const std::string& phase) {
        const size_t batch = std::min(req.queries, plan.queryBatch);
        const size_t batches = ceilDiv(req.queries, batch);
        const size_t k = std::max<uint32_t>(req.k, 1);
        add(phase, "knn: queries", batch, sizeof(PclKnnQuery), batches, batch);
        add(phase, "knn: counts", batch, sizeof(uint32_t), batches, batch);
        add(phase, "knn: indices", batch * k, sizeof(uint32_t), batches, batch);
        add(phase, "knn: dist2", batch * k, sizeof(float), batches, batch);
        add(phase, "knn: radius2", batch, sizeof(float), batches, batch);
    }

    const MemoryRequest& req;
    const MemoryLimits& lim;
    MemoryPlan& plan;
};

bool phaseEndsWith(const MemoryPhase& p, const std::string& suffix) {
    return p.name.size() >= suffix.size() && p.name.compare(p.name.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// "or raise --max-buffer-mib to at least 73", or why that would not help.
std::string raiseCap(const MemoryLimits& l, size_t bytes) {
    if (l.capped) return "raise --max-buffer-mib to at least " + std::to_string(ceilDiv(bytes, kMiB));
    return "use a device with a larger max allocation";
}

}  // namespace

MemoryLimits memoryLimits(const DeviceInfo& info) {
    MemoryLimits l;
    l.maxAlloc = info.maxAlloc;
    l.globalMem = info.globalMem;
    l.type = info.type;
    l.computeUnits = info.computeUnits;
    l.device = info.name;
    l.maxAllocSource = describeMaxAlloc(info);
    l.capped = info.bufferCap && info.bufferCap <= info.driverMaxAlloc;
    return l;
}

SceneBufferCounts sceneBufferCounts(const SceneGeometry& geometry, const SceneBuffers& buffers) {
    SceneBufferCounts s;
    s.nodes = geometry.nodes.size();
    s.packets = geometry.packets.size();
    s.spheres = geometry.spheres.size();
    s.materials = buffers.materials.size();
    s.primInfo = buffers.primInfo.size();
    s.lights = buffers.lights.size();
    s.projCells = buffers.projCells.size();
    s.media = buffers.hasMedia ? buffers.media.size() : 0;
    s.skyFloats = buffers.sky.data.size();
    s.texelFloats = buffers.textures.textured() ? buffers.textures.texels.size() : 0;
    s.triangleUvs = buffers.textures.textured() ? buffers.textures.triangleUvs.size() : 0;
    s.triangleNormals = buffers.triangleNormals.size();
    s.normalMaps = buffers.normalMaps.maps.size();
    s.triangleTangents = buffers.normalMaps.triangleTangents.size();
    return s;
}

MemoryRequest photonPassMemoryRequest(const SceneGeometry& geometry, const SceneBuffers& buffers,
                                      const PhotonPassOptions& options) {
    MemoryRequest r;
    r.scene = sceneBufferCounts(geometry, buffers);
    if (options.buildGlobal && options.globalPhotons)
        r.globalPaths = lightFirstPhoton(buffers, options.globalPhotons, PCL_PASS_GLOBAL).back();
    if (options.buildCaustic && options.causticPhotons)
        r.causticPaths = lightFirstPhoton(buffers, options.causticPhotons, PCL_PASS_CAUSTIC).back();
    r.maxDepth = options.maxDepth;
    r.photonBatch = options.batchSize;
    r.media = buffers.hasMedia;
    r.kdTree = false;
    return r;
}

size_t MemoryPlan::peakBytes() const {
    size_t peak = 0;
    for (const MemoryPhase& p : phases) peak = std::max(peak, p.bytes);
    return peak;
}

const PlannedBuffer* MemoryPlan::find(const std::string& phase, const std::string& what) const {
    for (const PlannedBuffer& b : buffers)
        if (b.phase == phase && b.what == what) return &b;
    return nullptr;
}

MemoryPlan planMemory(const MemoryRequest& request, const MemoryLimits& limits) {
    MemoryPlan plan;
    plan.limits = limits;
    // globalMem 0: unknown (no device at hand); only the max allocation is checked.
    const size_t globalMem = limits.globalMem ? limits.globalMem : SIZE_MAX;
    plan.budget = limits.globalMem ? size_t(double(limits.globalMem) * (1.0 - kMemoryHeadroom)) : SIZE_MAX;
    const bool gpu = (limits.type & CL_DEVICE_TYPE_GPU) != 0;
    const uint32_t slots = std::max<uint32_t>(request.maxDepth, 1);
    // With media the volume slots double the slot memory per path (as runPhotonPass sizes it).
    plan.photonBatch = request.photonBatch
                           ? request.photonBatch
                           : defaultPhotonBatch(limits.maxAlloc, gpu, slots * (request.media ? 2u : 1u));
    plan.queryBatch = request.queryBatch ? request.queryBatch
                                         : knnQueryBatch(limits.maxAlloc, globalMem, std::max<uint32_t>(request.k, 1));
    Planner planner(request, limits, plan);
    // Halve the divisible work while a phase it belongs to is over the budget (batches the
    // request fixed stay as they are: the problem is reported instead).
    for (;;) {
        planner.build();
        bool shrunk = false;
        for (const MemoryPhase& p : plan.phases) {
            if (p.bytes <= plan.budget) continue;
            if (phaseEndsWith(p, "photon pass") && !request.photonBatch && plan.photonBatch > kMinBatch) {
                plan.photonBatch = uint32_t(std::max<size_t>(plan.photonBatch / 2 / kMinBatch * kMinBatch, kMinBatch));
                shrunk = true;
            } else if (phaseEndsWith(p, "search") && !request.queryBatch && plan.queryBatch > kMinBatch) {
                plan.queryBatch = std::max<size_t>(plan.queryBatch / 2 / kMinBatch * kMinBatch, kMinBatch);
                shrunk = true;
            }
            if (shrunk) break;
        }
        if (!shrunk) break;
    }

    const std::string limit = "above the device's max allocation " + limits.maxAllocSource;
    // A map holds at least its requested records: checked on the records, not on the buffer's
    // first capacity (which initialMapCapacity clamps to the limit).
    struct MapCheck {
        const char* name;
        uint32_t paths;
        size_t records;
        const char* option;
    } maps[2] = {{"global", request.globalPaths, request.globalRecords ? request.globalRecords : request.globalPaths,
                  "--global-photons"},
                 {"caustic", request.causticPaths,
                  request.causticRecords ? request.causticRecords : request.causticPaths, "--caustic-photons"}};
    for (const MapCheck& m : maps) {
        const size_t bytes = m.records * sizeof(PclPhoton);
        if (!m.paths || bytes <= limits.maxAlloc) continue;
        const size_t most = size_t(double(m.paths) * double(maxMapRecords(limits.maxAlloc)) / double(m.records));
        plan.problems.push_back("the " + std::string(m.name) + " photon map needs at least " + formatMiB(bytes) + " (" +
                                std::to_string(m.records) + " records × " + std::to_string(sizeof(PclPhoton)) +
                                " bytes" + (m.records == m.paths ? ", one per emitted path" : "") + "), " + limit +
                                "; emit at most " + std::to_string(most) + " " + m.name + " photons (" + m.option +
                                ") or " + raiseCap(limits, bytes));
    }
    // Every other buffer: the largest one over the limit in each phase.
    for (const MemoryPhase& p : plan.phases) {
        const PlannedBuffer* worst = nullptr;
        for (const PlannedBuffer& b : plan.buffers)
            if (b.phase == p.name && b.bytes > limits.maxAlloc && (!worst || b.bytes > worst->bytes)) worst = &b;
        if (!worst) continue;
        std::string advice;
        if (worst->batches)
            advice = "use a smaller batch (at most " +
                     std::to_string(worst->perBatch * limits.maxAlloc / worst->bytes) + " per launch)";
        else if (worst->records)
            advice = "emit fewer photons (a map of at most " +
                     std::to_string(size_t(double(worst->records) * double(limits.maxAlloc) / double(worst->bytes))) +
                     " records fits)";
        else advice = "simplify the scene";
        plan.problems.push_back(p.name + ": " + worst->what + " needs " + formatMiB(worst->bytes) + " (" +
                                std::to_string(worst->count) + " × " + std::to_string(worst->elementBytes) +
                                " bytes), " + limit + "; " + advice + " or " + raiseCap(limits, worst->bytes));
    }
    for (const MemoryPhase& p : plan.phases)
        if (p.bytes > plan.budget)
            plan.problems.push_back(p.name + " needs " + gib(p.bytes) + " at once, above the budget of " +
                                    gib(plan.budget) + " (the device's global memory " + gib(limits.globalMem) +
                                    " less " + std::to_string(int(kMemoryHeadroom * 100)) +
                                    " % headroom) even with the smallest batches; emit fewer photons or search fewer "
                                    "queries at once");
    return plan;
}

void requireMemoryFits(const MemoryPlan& plan) {
    if (plan.fits()) return;
    std::string message = "memory plan on " + plan.limits.device + ": ";
    for (size_t i = 0; i < plan.problems.size(); ++i) message += (i ? "\n  " : "") + plan.problems[i];
    throw InputError(message);
}

std::string formatMemoryPlan(const MemoryPlan& plan) {
    std::ostringstream s;
    char line[256];
    s << "memory plan on " << plan.limits.device << ": max allocation " << plan.limits.maxAllocSource;
    if (plan.limits.globalMem)
        s << ", global memory " << gib(plan.limits.globalMem) << " (budget " << gib(plan.budget) << " per phase)\n";
    else s << ", global memory unknown (not checked)\n";
    std::snprintf(line, sizeof line, "  %-20s %-28s %12s %11s  %s\n", "phase", "buffer", "elements", "MiB", "launches");
    s << line;
    for (const PlannedBuffer& b : plan.buffers) {
        std::string launches;
        if (b.batches) launches = std::to_string(b.batches) + " × " + std::to_string(b.perBatch);
        const char* mark = b.bytes > plan.limits.maxAlloc ? "  OVER MAX ALLOCATION" : "";
        std::snprintf(line, sizeof line, "  %-20s %-28s %12zu %11.3f  %s%s\n", b.phase.c_str(), b.what.c_str(), b.count,
                      double(b.bytes) / double(kMiB), launches.c_str(), mark);
        s << line;
    }
    s << "  together:";
    const MemoryPhase* peak = nullptr;
    for (const MemoryPhase& p : plan.phases) {
        s << (peak ? "; " : " ") << p.name << " " << gib(p.bytes);
        if (!peak || p.bytes > peak->bytes) peak = &p;
    }
    s << "\n";
    if (peak) s << "  peak: " << gib(peak->bytes) << " (" << peak->name << ")\n";
    bool pass = false, search = false;
    for (const MemoryPhase& p : plan.phases) {
        pass = pass || phaseEndsWith(p, "photon pass");
        search = search || phaseEndsWith(p, "search");
    }
    if (pass) s << "  photon paths per launch: " << plan.photonBatch << "\n";
    if (search) s << "  kNN queries per launch: at most " << plan.queryBatch << "\n";
    if (pass)
        s << "  maps are planned at one record per photon emitted; the pass may store more or fewer, and a map that "
             "outgrows the max allocation fails when it grows\n";
    if (plan.fits())
        s << "  fits: every buffer under the max allocation"
          << (plan.limits.globalMem ? ", every phase under the budget" : "") << "\n";
    else
        for (const std::string& p : plan.problems) s << "  DOES NOT FIT: " << p << "\n";
    return s.str();
}

}  // namespace pcl
