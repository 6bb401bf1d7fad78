// The memory plan against the device (pipeline/memory_plan, Device::setBufferCap
// 7): the bytes it predicts for every buffer equal the bytes the stages allocate (observed
// through Device::setAllocationObserver, buffer by buffer); under a 64 MiB per-buffer cap the
// photon pass and a kNN search whose outputs pass 64 MiB split into more launches and give the
// same bits as without the cap; a buffer above the cap fails with a message naming it.
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "check/on_device.h"
#include "device_fixture.h"
#include "photon_test_scenes.h"
#include "pipeline/deposit.h"
#include "pipeline/kdtree.h"
#include "pipeline/knn.h"
#include "pipeline/memory_plan.h"
#include "pipeline/photon_pass.h"
#include "pipeline/volume_estimate.h"

namespace pcl {
namespace {

constexpr size_t kMiB = size_t(1) << 20;

std::string shippedScene(const char* name) { return std::string(PHOTONCL_SOURCE_DIR) + "/scenes/" + name; }

struct BuiltScene {
    Scene scene;
    SceneGeometry geometry;
    SceneBuffers buffers;
};

BuiltScene buildScene(const std::string& path) {
    BuiltScene b;
    b.scene = loadScene(path);
    b.geometry = SceneGeometry::build(b.scene);
    b.buffers = buildSceneBuffers(b.scene, b.geometry);
    buildProjectionMaps(b.scene, b.geometry, b.buffers);
    return b;
}

// Every allocation: the largest bytes per (phase, label), and the largest buffer overall.
struct AllocationLog {
    std::string phase;  // the phase the test is running; "scene:" labels always go to "scene"
    std::map<std::pair<std::string, std::string>, size_t> largest;
    size_t maxBytes = 0, count = 0;
    void observe(Device& device) {
        device.setAllocationObserver([this](const std::string& what, size_t bytes) {
            std::string p = what.rfind("scene:", 0) == 0 ? "scene" : phase;
            if (what.rfind("knn: ", 0) == 0 && what != "knn: packed kd-tree") p = mapName + " search";
            size_t& b = largest[{p, what}];
            b = std::max(b, bytes);
            maxBytes = std::max(maxBytes, bytes);
            ++count;
        });
    }
    std::string mapName = "global";
};

// `photons` paths for each map, 16 bounces.
PhotonPassOptions smallPasses(uint32_t photons) {
    PhotonPassOptions o;
    o.globalPhotons = photons;
    o.causticPhotons = photons;
    o.maxDepth = 16;
    return o;
}

// A global pass, then a caustic pass, with options o (each building its own map), logged under
// the phases "global photon pass" and "caustic photon pass": {global pass's maps, caustic pass's}.
std::pair<PhotonMaps, PhotonMaps> runBothPasses(Device& device, const BuiltScene& s, const PhotonPassOptions& o,
                                                AllocationLog& log) {
    std::pair<PhotonMaps, PhotonMaps> maps;
    for (bool global : {true, false}) {
        PhotonPassOptions one = o;
        one.buildGlobal = global;
        one.buildCaustic = !global;
        log.phase = global ? "global photon pass" : "caustic photon pass";
        (global ? maps.first : maps.second) = runPhotonPass(device, s.geometry, s.buffers, one);
    }
    return maps;
}

std::vector<PclPhoton> randomMap(size_t n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclPhoton> map(n);
    for (PclPhoton& p : map) {
        p = PclPhoton{};
        p.x = u(rng), p.y = u(rng), p.z = u(rng);
    }
    return map;
}

std::vector<PclKnnQuery> randomQueries(size_t n, uint32_t k, float radius, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclKnnQuery> qs(n);
    for (PclKnnQuery& q : qs) {
        q = PclKnnQuery{};
        q.x = u(rng), q.y = u(rng), q.z = u(rng);
        q.maxRadius2 = radius * radius;
        q.k = k;
    }
    return qs;
}

template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

TEST(MemoryPlan, CapLowersMaxAllocAndRefusesLargerBuffersByName) {
    Device device = test::testDevice();  // a copy: the shared device keeps its limits
    const size_t driver = device.info().driverMaxAlloc;
    ASSERT_EQ(device.info().maxAlloc, driver);
    device.setBufferCap(64 * kMiB);
    EXPECT_EQ(device.info().maxAlloc, std::min(driver, 64 * kMiB));
    EXPECT_EQ(test::testDevice().info().maxAlloc, driver);
    EXPECT_NO_THROW(device.allocate<uint32_t>(16 * kMiB, CL_MEM_READ_WRITE, "test: exactly 64 MiB"));
    try {
        device.allocate<uint32_t>(16 * kMiB + 1, CL_MEM_READ_WRITE, "test stage: big buffer");
        FAIL() << "a buffer above the cap was allocated";
    } catch (const DeviceError& e) {
        const std::string m = e.what();
        std::printf("[figure] over-cap message: %s\n", m.c_str());
        EXPECT_NE(m.find("test stage: big buffer needs 64.0 MiB (67108868 bytes)"), std::string::npos) << m;
        EXPECT_NE(m.find("above the device's max allocation 64.0 MiB (cap from --max-buffer-mib)"), std::string::npos)
            << m;
    }
    device.setBufferCap(0);
    EXPECT_EQ(device.info().maxAlloc, driver);
}

// Both maps of a scene with caustics, a kd-tree and a hash grid per map, a kNN search: every
// planned buffer is allocated with exactly the predicted bytes, and nothing unplanned is.
TEST(MemoryPlan, PredictedBytesEqualAllocatedBytesForEveryBuffer) {
    const BuiltScene s = buildScene(shippedScene("cornell-spheres.json"));
    Device device = test::testDevice();
    AllocationLog log;
    log.observe(device);

    PhotonPassOptions o = smallPasses(20000);
    o.batchSize = 8192;  // several batches and a partial last one
    const auto [globalPass, causticPass] = runBothPasses(device, s, o, log);
    ASSERT_EQ(globalPass.stats.global.growths, 0u) << "the initial capacity was predicted";
    ASSERT_EQ(causticPass.stats.caustic.growths, 0u) << "the initial capacity was predicted";
    PhotonMaps maps;
    maps.global = globalPass.global;
    maps.caustic = causticPass.caustic;
    ASSERT_GT(maps.global.size(), 1000u);
    ASSERT_GT(maps.caustic.size(), 100u);

    MemoryRequest req = photonPassMemoryRequest(s.geometry, s.buffers, o);
    req.globalRecords = maps.global.size();
    req.causticRecords = maps.caustic.size();
    req.kdTree = req.hashGrid = true;
    req.queries = 3000;
    req.k = 50;
    for (const char* name : {"global", "caustic"}) {
        const std::vector<PclPhoton>& map = std::string(name) == "global" ? maps.global : maps.caustic;
        const std::vector<PclKnnQuery> qs = randomQueries(req.queries, req.k, 0.2f, 7);
        log.mapName = name;
        log.phase = std::string(name) + " kd-tree";
        knnOnDevice(device, map, KnnStructure::KdTree, qs);
        log.phase = std::string(name) + " hash grid";
        knnOnDevice(device, map, KnnStructure::HashGrid, qs);
    }
    device.setAllocationObserver(nullptr);

    const MemoryPlan plan = planMemory(req, memoryLimits(device.info()));
    ASSERT_TRUE(plan.fits()) << formatMemoryPlan(plan);
    EXPECT_EQ(plan.photonBatch, 8192u);
    std::printf("%s", formatMemoryPlan(plan).c_str());
    std::map<std::string, std::pair<size_t, size_t>> byPhase;  // predicted, allocated
    for (const PlannedBuffer& b : plan.buffers) {
        auto it = log.largest.find({b.phase, b.what});
        ASSERT_NE(it, log.largest.end()) << b.phase << " / " << b.what << " was planned but never allocated";
        EXPECT_EQ(it->second, b.bytes) << b.phase << " / " << b.what;
        byPhase[b.phase].first += b.bytes;
        byPhase[b.phase].second += it->second;
    }
    for (const auto& [key, bytes] : log.largest)
        EXPECT_NE(plan.find(key.first, key.second), nullptr)
            << key.first << " / " << key.second << " (" << bytes << " bytes) was allocated but not planned";
    for (const auto& [phase, b] : byPhase)
        std::printf("[figure] %-20s predicted %10zu bytes, allocated %10zu bytes\n", phase.c_str(), b.first, b.second);
    std::printf("[figure] %zu buffers planned, %zu allocations observed\n", plan.buffers.size(), log.count);
}

#ifdef PHOTONCL_HAVE_GLTF  // the courtyard's geometry is glTF (the build for the GPU machine reads none)
// The courtyard: image textures, a normal map with its tangents, per-vertex normals and an image
// sky. Every scene buffer the photon pass allocates for them is planned to the byte, and every
// planned scene buffer is allocated.
TEST(MemoryPlan, TexturedSkyLitScenePlansEverySceneBuffer) {
    const BuiltScene s = buildScene(shippedScene("courtyard/courtyard.json"));
    ASSERT_FALSE(s.scene.textures.empty());
    ASSERT_TRUE(s.scene.environment.active());
    Device device = test::testDevice();
    AllocationLog log;
    log.observe(device);
    const PhotonPassOptions o = smallPasses(5000);
    runBothPasses(device, s, o, log);
    device.setAllocationObserver(nullptr);
    const MemoryPlan plan = planMemory(photonPassMemoryRequest(s.geometry, s.buffers, o), memoryLimits(device.info()));
    size_t sceneBuffers = 0, planned = 0;
    for (const auto& [key, bytes] : log.largest) {
        if (key.first != "scene") continue;
        ++sceneBuffers;
        const PlannedBuffer* b = plan.find(key.first, key.second);
        ASSERT_NE(b, nullptr) << key.second << " (" << bytes << " bytes) was allocated but not planned";
        EXPECT_EQ(b->bytes, bytes) << key.second;
        planned += b->bytes;
    }
    for (const PlannedBuffer& b : plan.buffers) {
        if (b.phase == "scene") {
            EXPECT_TRUE(log.largest.count({b.phase, b.what})) << b.what << " was planned but never allocated";
        }
    }
    for (const char* what : {"scene: texels", "scene: environment"}) {
        bool found = false;
        for (const auto& [key, bytes] : log.largest) found = found || key.second.rfind(what, 0) == 0;
        EXPECT_TRUE(found) << what << "... was never allocated";
    }
    std::printf("[figure] courtyard: %zu scene buffers, %zu bytes, each as planned\n", sceneBuffers, planned);
}
#endif

// A scene with media: the media buffers, the volume slots and counts and each pass's volume map
// are planned to the byte as allocated (a volume map that outgrows its first capacity is
// allocated again larger: at least the planned bytes), and the batch is sized for both slot
// buffers.
TEST(MemoryPlan, PhotonPassWithMediaPlansTheVolumeBuffers) {
    const BuiltScene s = buildScene(std::string(PHOTONCL_SOURCE_DIR) + "/scenes/media/cornell-fog.json");
    ASSERT_TRUE(s.buffers.hasMedia);
    Device device = test::testDevice();
    AllocationLog log;
    log.observe(device);
    const PhotonPassOptions o = smallPasses(20000);
    const auto [globalPass, causticPass] = runBothPasses(device, s, o, log);
    ASSERT_GT(globalPass.volume.size(), 0u);
    ASSERT_GT(causticPass.volumeCaustic.size(), 0u);
    device.setAllocationObserver(nullptr);

    MemoryRequest req = photonPassMemoryRequest(s.geometry, s.buffers, o);
    EXPECT_TRUE(req.media);
    const MemoryPlan plan = planMemory(req, memoryLimits(device.info()));
    EXPECT_EQ(plan.photonBatch, defaultPhotonBatch(device, 2 * o.maxDepth));
    size_t volumeBuffers = 0;
    for (const PlannedBuffer& b : plan.buffers) {
        auto it = log.largest.find({b.phase, b.what});
        ASSERT_NE(it, log.largest.end()) << b.phase << " / " << b.what << " was planned but never allocated";
        const bool grows = b.what.find(" map") != std::string::npos;  // maps may outgrow the first capacity
        if (grows) EXPECT_GE(it->second, b.bytes) << b.phase << " / " << b.what;
        else EXPECT_EQ(it->second, b.bytes) << b.phase << " / " << b.what;
        volumeBuffers += b.what.find("volume") != std::string::npos || b.what.find("media") != std::string::npos;
    }
    for (const auto& [key, bytes] : log.largest)
        EXPECT_NE(plan.find(key.first, key.second), nullptr)
            << key.first << " / " << key.second << " (" << bytes << " bytes) was allocated but not planned";
    EXPECT_EQ(volumeBuffers, 3u + 2u * 3u);  // scene: 3; per pass: slots, counts, map
}

// The volume estimate: the map's device copy, its hash grid (with its build's scratch) and the
// radiance of one launch are planned to the byte as buildVolumeMap and estimateVolumeRadiance
// allocate them (the segments, counts and media come from elsewhere: uploaded unobserved).
TEST(MemoryPlan, VolumeEstimatePlansItsMapGridAndRadiance) {
    Device device = test::testDevice();
    std::vector<PclPhoton> photons = randomMap(30000, 5);
    for (PclPhoton& p : photons) p.packed = PCL_PHOTON_VOLUME | (1u << PCL_PHOTON_BOUNCE_SHIFT);
    VolumeSegments s;
    s.sampleCount = 5000;
    s.maxSegments = 1;
    s.segments.assign(s.sampleCount, PclVolumeSegment{});
    s.counts.assign(s.sampleCount, 0u);
    const cl::Buffer segs = device.upload(s.segments), counts = device.upload(s.counts);
    PclMedium m{};
    const cl::Buffer media = device.upload(std::vector<PclMedium>{m});
    AllocationLog log;
    log.observe(device);
    for (const char* name : {"global", "caustic"}) {
        log.phase = std::string(name) + " volume estimate";
        const std::vector<PclPhoton> map(photons.begin(), photons.begin() + (name[0] == 'g' ? 30000 : 7000));
        VolumeEstimateSettings settings;
        settings.radius = 0.05f;
        const DeviceVolumeMap vm = buildVolumeMap(device, map, settings);
        const PclVolumeEstimateParams p = volumeEstimateParams(vm, settings, s.sampleCount, 1, 1);
        estimateVolumeRadiance(device, vm, p, segs, counts, media);
    }
    device.setAllocationObserver(nullptr);
    MemoryRequest req;
    req.volumeRecords = 30000;
    req.volumeCausticRecords = 7000;
    req.volumeQueries = s.sampleCount;
    const MemoryPlan plan = planMemory(req, memoryLimits(device.info()));
    size_t planned = 0;
    for (const PlannedBuffer& b : plan.buffers) {
        if (b.phase.find("volume estimate") == std::string::npos) continue;
        ++planned;
        auto it = log.largest.find({b.phase, b.what});
        ASSERT_NE(it, log.largest.end()) << b.phase << " / " << b.what << " was planned but never allocated";
        EXPECT_EQ(it->second, b.bytes) << b.phase << " / " << b.what;
    }
    for (const auto& [key, bytes] : log.largest)
        EXPECT_NE(plan.find(key.first, key.second), nullptr)
            << key.first << " / " << key.second << " (" << bytes << " bytes) was allocated but not planned";
    EXPECT_EQ(planned, log.largest.size());
    EXPECT_GE(planned, 2u * 8u);  // photons, 5 grid buffers, ≥ 1 sort buffer, radiance; per map
}

// A map large enough that the kd-tree's top levels are split a level at a time (the chunk-count
// buffer): predicted as built.
TEST(MemoryPlan, LargeKdTreeBuildIsPredictedWithItsChunkCounts) {
    const size_t n = 800000;
    const std::vector<PclPhoton> map = randomMap(n, 11);
    Device device = test::testDevice();
    AllocationLog log;
    log.phase = "global kd-tree";
    log.observe(device);
    cl::Buffer photons = device.upload(map, CL_MEM_READ_ONLY, "kd-tree: photons");
    packKdTree(device, buildKdTree(device, photons, n));
    device.setAllocationObserver(nullptr);

    MemoryRequest req;
    req.globalPaths = uint32_t(n);
    const MemoryPlan plan = planMemory(req, memoryLimits(device.info()));
    ASSERT_GT(kdTreeCountEntries(n, kdTreeFinishSize(device.info().type), device.info().type), 0u);
    size_t checked = 0;
    for (const PlannedBuffer& b : plan.buffers) {
        if (b.phase != "global kd-tree") continue;
        auto it = log.largest.find({b.phase, b.what});
        ASSERT_NE(it, log.largest.end()) << b.what << " was planned but never allocated";
        EXPECT_EQ(it->second, b.bytes) << b.what;
        ++checked;
    }
    for (const auto& [key, bytes] : log.largest)
        EXPECT_NE(plan.find(key.first, key.second), nullptr) << key.second << " was allocated but not planned";
    EXPECT_NE(plan.find("global kd-tree", "kd-tree: chunk counts"), nullptr);
    size_t phaseBytes = 0;
    for (const MemoryPhase& p : plan.phases)
        if (p.name == "global kd-tree") phaseBytes = p.bytes;
    std::printf(
        "[figure] kd-tree of %zu photons: %zu buffers predicted to the byte, %zu allocations, %.1f MiB at once\n", n,
        checked, log.count, double(phaseBytes) / kMiB);
}

// Enough paths × slots that the uncapped slot buffer passes 64 MiB: under the cap the pass runs
// in more, smaller batches and stores the same records, bit for bit.
TEST(MemoryPlan, PhotonPassUnderA64MiBCapEqualsUncapped) {
    const BuiltScene s = buildScene(shippedScene("cornell-box.json"));
    PhotonPassOptions o;
    o.globalPhotons = 100000;
    o.maxDepth = 64;
    o.buildCaustic = false;

    Device uncapped = test::testDevice();
    AllocationLog freeLog;
    freeLog.observe(uncapped);
    const PhotonMaps a = runPhotonPass(uncapped, s.geometry, s.buffers, o);

    Device capped = test::testDevice();
    capped.setBufferCap(64 * kMiB);
    AllocationLog capLog;
    capLog.observe(capped);
    const MemoryPlan plan = planMemory(photonPassMemoryRequest(s.geometry, s.buffers, o), memoryLimits(capped.info()));
    requireMemoryFits(plan);
    const PhotonMaps b = runPhotonPass(capped, s.geometry, s.buffers, o);

    std::printf("[figure] uncapped: %u batches of %u, largest buffer %.1f MiB; 64 MiB cap: %u batches of %u (plan: "
                "%u), largest %.1f MiB; %zu records\n",
                a.stats.global.batches, a.stats.global.batchSize, double(freeLog.maxBytes) / kMiB,
                b.stats.global.batches, b.stats.global.batchSize, plan.photonBatch, double(capLog.maxBytes) / kMiB,
                a.global.size());
    EXPECT_GT(freeLog.maxBytes, 64 * kMiB) << "the uncapped slot buffer should pass the cap for this test to mean much";
    EXPECT_LE(capLog.maxBytes, 64 * kMiB);
    EXPECT_GT(b.stats.global.batches, a.stats.global.batches);
    EXPECT_EQ(b.stats.global.batchSize, plan.photonBatch);
    ASSERT_GT(a.global.size(), 100000u);
    EXPECT_TRUE(sameBits(a.global, b.global));
    EXPECT_EQ(a.stats.global.absorbed, b.stats.global.absorbed);
    EXPECT_EQ(a.stats.global.escaped, b.stats.global.escaped);
}

// A search whose index and distance outputs pass 64 MiB each: under the cap it runs in several
// launches and returns the same neighbours and distances, bit for bit.
TEST(MemoryPlan, KnnUnderA64MiBCapEqualsUncapped) {
    const uint32_t k = 100;
    const size_t queries = 172032;  // × k × 4 bytes = 65.6 MiB per output
    const std::vector<PclPhoton> map = randomMap(30000, 3);
    // A radius holding ~12 photons on average: the outputs are sized by k all the same, and the
    // search stays quick (a full k = 100 per query costs seconds under PoCL).
    const std::vector<PclKnnQuery> qs = randomQueries(queries, k, 0.046f, 5);

    Device uncapped = test::testDevice();
    AllocationLog freeLog;
    freeLog.observe(uncapped);
    const KnnResult a = knnOnDevice(uncapped, map, KnnStructure::KdTree, qs);

    Device capped = test::testDevice();
    capped.setBufferCap(64 * kMiB);
    AllocationLog capLog;
    capLog.observe(capped);
    const KnnResult b = knnOnDevice(capped, map, KnnStructure::KdTree, qs);

    const size_t batch = knnQueryBatch(capped.info().maxAlloc, capped.info().globalMem, k);
    std::printf("[figure] kNN %zu queries k = %u: uncapped largest buffer %.1f MiB in one launch; 64 MiB cap: %zu "
                "launches of %zu, largest %.1f MiB; search %.3f s vs %.3f s\n",
                queries, k, double(freeLog.maxBytes) / kMiB, (queries + batch - 1) / batch, batch,
                double(capLog.maxBytes) / kMiB, a.searchSeconds, b.searchSeconds);
    const size_t uncappedIndices =
        freeLog.largest[std::make_pair(std::string("global search"), std::string("knn: indices"))];
    EXPECT_GT(uncappedIndices, 64 * kMiB);
    EXPECT_LE(capLog.maxBytes, 64 * kMiB);
    EXPECT_GT((queries + batch - 1) / batch, 1u);
    size_t found = 0, most = 0;
    for (uint32_t c : a.counts) found += c, most = std::max<size_t>(most, c);
    std::printf("[figure] neighbours found: mean %.1f, most %zu\n", double(found) / queries, most);
    EXPECT_GT(found, 8 * queries) << "the queries should find neighbours";
    EXPECT_EQ(a.stride, b.stride);
    EXPECT_TRUE(sameBits(a.counts, b.counts));
    EXPECT_TRUE(sameBits(a.indices, b.indices));
    EXPECT_TRUE(sameBits(a.dist2, b.dist2));
    EXPECT_TRUE(sameBits(a.radius2, b.radius2));
}

// depositOnDevice (the deposit check) with more slots than one buffer may hold: deposited in
// chunks of paths, the same map.
TEST(MemoryPlan, DepositCheckSplitsUnderTheCap) {
    const uint32_t S = 16;
    const size_t paths = 3500;  // 1.3 MiB of slots, a map of ~0.6 MiB
    std::mt19937 rng(9);
    std::vector<uint32_t> counts(paths);
    std::vector<PclPhoton> slots(paths * S);
    for (size_t i = 0; i < paths; ++i) {
        counts[i] = rng() % (S + 1);
        for (uint32_t k = 0; k < counts[i]; ++k) {
            PclPhoton& p = slots[i * S + k];
            p.x = float(i), p.y = float(k), p.z = float(rng() % 1000);
            p.rgbe = uint32_t(rng());
        }
    }
    Device capped = test::testDevice();
    capped.setBufferCap(1 * kMiB);
    AllocationLog log;
    log.observe(capped);
    const std::vector<PclPhoton> a = depositOnDevice(test::testDevice(), counts, slots, S);
    const std::vector<PclPhoton> b = depositOnDevice(capped, counts, slots, S);
    EXPECT_LE(log.maxBytes, 1 * kMiB);
    ASSERT_GT(a.size(), paths * 4);
    EXPECT_TRUE(sameBits(a, b));
}

// A map that turns out larger than its photon count (the plan's assumption) stops growing at the
// cap and fails there with the same kind of message.
TEST(MemoryPlan, MapOutgrowingTheCapMidPassFailsWithItsName) {
    const BuiltScene s = buildScene(shippedScene("cornell-box.json"));
    Device device = test::testDevice();
    device.setBufferCap(1 * kMiB);  // 43690 records
    PhotonPassOptions o;
    o.globalPhotons = 40000;  // fits the plan (one record per path) but stores ~1.75 per path
    o.maxDepth = 8;
    o.buildCaustic = false;
    requireMemoryFits(planMemory(photonPassMemoryRequest(s.geometry, s.buffers, o), memoryLimits(device.info())));
    try {
        runPhotonPass(device, s.geometry, s.buffers, o);
        FAIL() << "a map above the cap was built";
    } catch (const InputError& e) {
        const std::string m = e.what();
        std::printf("[figure] growth message: %s\n", m.c_str());
        EXPECT_NE(m.find("photon pass: global map needs"), std::string::npos) << m;
        EXPECT_NE(m.find("1.0 MiB (cap from --max-buffer-mib), which holds 43690 records"), std::string::npos) << m;
    }
}

}  // namespace
}  // namespace pcl
