// The memory plan on made-up limits (pipeline/memory_plan; no device needed) and the
// --max-buffer-mib option end to end: batches chosen under the max allocation and the global
// memory budget, a map that cannot fit refused before any work with a message that names it,
// the bytes and the limit; `photoncl photons --max-buffer-mib 64` writes the same PLY bytes as
// without the cap, and a cap of 0 is rejected.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "core/error.h"
#include "pipeline/memory_plan.h"
#include "run_photoncl.h"

namespace pcl {
namespace {

constexpr size_t kMiB = size_t(1) << 20;

MemoryLimits cpuLimits(size_t maxAlloc, size_t globalMem, bool capped = true) {
    MemoryLimits l;
    l.maxAlloc = maxAlloc;
    l.globalMem = globalMem;
    l.type = CL_DEVICE_TYPE_CPU;
    l.device = "test CPU";
    l.capped = capped;
    l.maxAllocSource = formatMiB(maxAlloc) + (capped ? " (cap from --max-buffer-mib)" : " (the driver's)");
    return l;
}

MemoryRequest smallScene() {
    MemoryRequest r;
    r.scene.nodes = 10;
    r.scene.packets = 20;
    r.scene.materials = 4;
    r.scene.primInfo = 80;
    r.scene.lights = 2;
    return r;
}

size_t largestDivisible(const MemoryPlan& plan) {
    size_t m = 0;
    for (const PlannedBuffer& b : plan.buffers)
        if (b.batches) m = std::max(m, b.bytes);
    return m;
}

TEST(MemoryPlanUnit, BatchesSplitUnderTheCapAndEveryBufferFits) {
    MemoryRequest r = smallScene();
    r.globalPaths = 1000000;
    r.causticPaths = 200000;
    r.maxDepth = 64;
    r.queries = 1 << 20;
    r.k = 100;
    const MemoryPlan free = planMemory(r, cpuLimits(6 * (size_t(1) << 30), 24 * (size_t(1) << 30), false));
    const MemoryPlan capped = planMemory(r, cpuLimits(64 * kMiB, 24 * (size_t(1) << 30)));
    ASSERT_TRUE(free.fits()) << formatMemoryPlan(free);
    ASSERT_TRUE(capped.fits()) << formatMemoryPlan(capped);
    std::printf("%s", formatMemoryPlan(capped).c_str());
    EXPECT_EQ(free.photonBatch, 65536u);    // 2^16 on a CPU
    EXPECT_EQ(capped.photonBatch, 10240u);  // 16 MiB of slots / (64 × 24 B), whole 1024s
    EXPECT_EQ(capped.queryBatch, 167744u);  // 64 MiB / (100 × 4 B), whole 64s
    for (const PlannedBuffer& b : capped.buffers) EXPECT_LE(b.bytes, 64 * kMiB) << b.what;
    const PlannedBuffer* slots = capped.find("global photon pass", "photon pass: slots");
    ASSERT_NE(slots, nullptr);
    EXPECT_EQ(slots->bytes, 10240u * 64u * 24u);
    EXPECT_EQ(slots->batches, 98u);  // ⌈1e6 / 10240⌉
    const PlannedBuffer* indices = capped.find("global search", "knn: indices");
    ASSERT_NE(indices, nullptr);
    EXPECT_EQ(indices->batches, 7u);               // ⌈2^20 / 167744⌉
    EXPECT_GT(largestDivisible(free), 64 * kMiB);  // uncapped, the same work has buffers above the cap
    const PlannedBuffer* map = capped.find("global photon pass", "photon pass: global map");
    ASSERT_NE(map, nullptr);
    EXPECT_EQ(map->count, 2000000u);  // 2 records per global path to start with
    EXPECT_EQ(capped.find("caustic photon pass", "photon pass: caustic map")->count, 200000u);
    std::printf("[figure] 64 MiB cap: %u paths per launch (uncapped %u), %zu queries per launch (uncapped %zu), peak "
                "%.1f MiB (uncapped %.1f MiB)\n",
                capped.photonBatch, free.photonBatch, capped.queryBatch, free.queryBatch,
                double(capped.peakBytes()) / kMiB, double(free.peakBytes()) / kMiB);
}

TEST(MemoryPlanUnit, MapAboveTheCapFailsBeforeWorkNamingItAndTheFix) {
    MemoryRequest r = smallScene();
    r.globalPaths = 3000000;  // 72 MB of records under a 64 MiB cap
    const MemoryPlan plan = planMemory(r, cpuLimits(64 * kMiB, 24 * (size_t(1) << 30)));
    ASSERT_FALSE(plan.fits());
    try {
        requireMemoryFits(plan);
        FAIL() << "no error";
    } catch (const InputError& e) {
        const std::string m = e.what();
        std::printf("[figure] message: %s\n", m.c_str());
        EXPECT_NE(m.find("the global photon map needs at least 68.7 MiB (3000000 records × 24 bytes"),
                  std::string::npos)
            << m;
        EXPECT_NE(m.find("above the device's max allocation 64.0 MiB (cap from --max-buffer-mib)"), std::string::npos)
            << m;
        EXPECT_NE(m.find("emit at most 2796202 global photons (--global-photons)"), std::string::npos) << m;
        EXPECT_NE(m.find("raise --max-buffer-mib to at least 69"), std::string::npos) << m;
        EXPECT_NE(m.find("global kd-tree: kd-tree: "), std::string::npos) << m;  // its kd-tree cannot be built either
    }
    r.globalPaths = 2796202;  // the advice holds
    EXPECT_TRUE(planMemory(r, cpuLimits(64 * kMiB, 24 * (size_t(1) << 30))).fits());
    // Without a cap the advice is another device, not a larger cap.
    r.globalPaths = 3000000;
    const MemoryPlan driver = planMemory(r, cpuLimits(64 * kMiB, 24 * (size_t(1) << 30), false));
    ASSERT_FALSE(driver.fits());
    EXPECT_NE(driver.problems[0].find("use a device with a larger max allocation"), std::string::npos);
}

TEST(MemoryPlanUnit, SmallGlobalMemoryShrinksTheBatchesOrFails) {
    MemoryRequest r = smallScene();
    r.globalPaths = 1000000;
    r.maxDepth = 64;
    r.kdTree = false;
    // 200 MiB of global memory: the default batch's 96 MiB of slots plus the 45.8 MiB map is fine,
    // at 120 MiB the batch must shrink to fit the 108 MiB budget.
    const MemoryPlan roomy = planMemory(r, cpuLimits(1024 * kMiB, 200 * kMiB, false));
    const MemoryPlan tight = planMemory(r, cpuLimits(1024 * kMiB, 120 * kMiB, false));
    ASSERT_TRUE(roomy.fits()) << formatMemoryPlan(roomy);
    ASSERT_TRUE(tight.fits()) << formatMemoryPlan(tight);
    EXPECT_EQ(roomy.photonBatch, 65536u);
    EXPECT_LT(tight.photonBatch, roomy.photonBatch);
    for (const MemoryPhase& p : tight.phases) EXPECT_LE(p.bytes, tight.budget) << p.name;
    std::printf("[figure] 120 MiB of global memory: %u paths per launch (200 MiB: %u), peak %.1f MiB\n",
                tight.photonBatch, roomy.photonBatch, double(tight.peakBytes()) / kMiB);
    // 40 MiB: the map alone (45.8 MiB) is over the budget, whatever the batch.
    const MemoryPlan none = planMemory(r, cpuLimits(1024 * kMiB, 40 * kMiB, false));
    ASSERT_FALSE(none.fits());
    EXPECT_NE(none.problems[0].find("global photon pass needs"), std::string::npos) << none.problems[0];
    EXPECT_NE(none.problems[0].find("10 % headroom"), std::string::npos) << none.problems[0];
}

// ---- --max-buffer-mib end to end ------------------------------------------------------------

std::string scene(const std::string& name) { return std::string(PHOTONCL_SOURCE_DIR) + "/scenes/" + name; }

std::string readFile(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

struct TempFolder {
    std::filesystem::path path = std::filesystem::temp_directory_path() /
                                 ("photoncl_memory_" + std::to_string(::getpid()));
    TempFolder() { std::filesystem::create_directories(path); }
    ~TempFolder() { std::filesystem::remove_all(path); }
};

TEST(MemoryPlanCli, PhotonsUnderA64MiBCapWritesTheSameBytes) {
    TempFolder dir;
    const std::string a = (dir.path / "a.ply").string(), b = (dir.path / "b.ply").string();
    const std::string common = "photons " + scene("cornell-spheres.json") +
                               " --global-photons 30000 --caustic-photons 20000";
    photoncl_cli::Result ra = photoncl_cli::run(common + " -o " + a);
    photoncl_cli::Result rb = photoncl_cli::run(common + " --max-buffer-mib 64 -o " + b);
    ASSERT_EQ(ra.status, 0) << ra.output;
    ASSERT_EQ(rb.status, 0) << rb.output;
    EXPECT_NE(ra.output.find("in 1 batches of 30000"), std::string::npos) << ra.output;
    EXPECT_NE(rb.output.find("in 3 batches of 10240"), std::string::npos) << rb.output;
    const std::string bytesA = readFile(a), bytesB = readFile(b);
    EXPECT_GT(bytesA.size(), 30000u * 20u);
    EXPECT_TRUE(bytesA == bytesB) << "the capped PLY differs";
}

TEST(MemoryPlanCli, MapThatCannotFitFailsBeforeWorkAndWritesNothing) {
    TempFolder dir;
    const std::filesystem::path out = dir.path / "big.ply";
    photoncl_cli::Result r = photoncl_cli::run("photons " + scene("cornell-box.json") +
                                               " --global-photons 3000000 --max-buffer-mib 64 -o " + out.string());
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("the global photon map needs at least 68.7 MiB"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("64.0 MiB (cap from --max-buffer-mib)"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("paths in"), std::string::npos) << "the pass ran: " << r.output;
    EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(MemoryPlanCli, ZeroOrJunkCapIsRejectedOnEveryCommand) {
    const std::string s = scene("cornell-box.json");
    for (const std::string& cmd : {"photons " + s + " -o /tmp/photoncl_never.ply", "check " + s + " --stage sort",
                                   "render " + s + " -o /tmp/photoncl_never.exr", "analyze " + s}) {
        for (const char* bad : {"0", "-3", "1.5", "lots"}) {
            photoncl_cli::Result r = photoncl_cli::run(cmd + " --max-buffer-mib " + bad);
            EXPECT_EQ(r.status, 2) << cmd << " " << bad << ": " << r.output;
            EXPECT_NE(r.output.find("--max-buffer-mib"), std::string::npos) << r.output;
        }
    }
    photoncl_cli::Result r = photoncl_cli::run("photons " + s + " --max-buffer-mib 0 -o /tmp/photoncl_never.ply");
    EXPECT_NE(r.output.find("expected a whole number of MiB from 1"), std::string::npos) << r.output;
}

TEST(MemoryPlanCli, AnalyzePrintsThePlanForTheCap) {
    photoncl_cli::Result r = photoncl_cli::run("analyze " + scene("cornell-box.json") + " --max-buffer-mib 64");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("memory plan on"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("64.0 MiB (cap from --max-buffer-mib)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("photon pass: slots"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("photon paths per launch: 10240"), std::string::npos) << r.output;
    photoncl_cli::Result big =
        photoncl_cli::run("analyze " + scene("cornell-box.json") + " --global-photons 3000000 --max-buffer-mib 64");
    EXPECT_EQ(big.status, 2) << big.output;
    EXPECT_NE(big.output.find("DOES NOT FIT: the global photon map needs at least 68.7 MiB"), std::string::npos)
        << big.output;
}

}  // namespace
}  // namespace pcl
