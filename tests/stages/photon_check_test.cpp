// The photon-pass kernels (emit, trace_photons, deposit) against their CPU twin
// (host/reference/) on every shipped scene, through the same checks `photoncl check --stage
// emit|trace|deposit|pass` runs (check/photon_stages.h states the tolerances): emit with no
// mismatch, trace with at most 0.1 % divergent paths per pass, deposit byte for byte. Photon
// counts are modest so the file stays within ~30 s on PoCL with two busy cores. And the check
// can fail: corrupted device results are caught.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>

#include "check/on_device.h"
#include "check/photon_stages.h"
#include "device_fixture.h"
#include "pipeline/deposit.h"
#include "pipeline/emit.h"
#include "pipeline/trace_photons.h"
#include "prep/projection_map.h"
#include "reference/deposit.h"
#include "reference/emit.h"
#include "reference/photon_pass.h"
#include "reference/trace_photons.h"
#include "scene/load_scene.h"

namespace pcl {
namespace {

std::vector<std::string> shippedScenes() {
    std::vector<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(std::string(PHOTONCL_SOURCE_DIR) + "/scenes")) {
        const std::string ext = e.path().extension().string();
#ifdef PHOTONCL_HAVE_GLTF
        if (ext == ".gltf" || ext == ".glb") out.push_back(e.path().string());
#endif
        if (ext == ".json") out.push_back(e.path().string());
    }
    std::sort(out.begin(), out.end());
    return out;
}

// Geometry, buffers and projection maps built once per scene for all three stages.
struct Prepared {
    Scene scene;
    SceneGeometry geometry;
    SceneBuffers buffers;
};
const Prepared& prepared(const std::string& path) {
    static std::map<std::string, std::unique_ptr<Prepared>> cache;
    auto& p = cache[path];
    if (!p) {
        p = std::make_unique<Prepared>();
        p->scene = loadScene(path);
        p->geometry = SceneGeometry::build(p->scene);
        p->buffers = buildSceneBuffers(p->scene, p->geometry);
        buildProjectionMaps(p->scene, p->geometry, p->buffers);
    }
    return *p;
}

PhotonCheckReport run(const std::string& path, const char* stage, uint32_t photons) {
    const Prepared& p = prepared(path);
    PhotonCheckOptions o;
    o.photons = photons;
    o.seed = 42;
    PhotonCheckReport r = checkPhotonStage(test::testDevice(), p.geometry, p.buffers, stage, o);
    std::printf("%s --stage %s, %u photons per pass\n%s", std::filesystem::path(path).filename().c_str(), stage,
                photons, r.table().c_str());
    return r;
}

class PhotonCheck : public ::testing::TestWithParam<std::string> {};

TEST_P(PhotonCheck, EmitMatchesTheTwin) {
    PhotonCheckReport r = run(GetParam(), "emit", 50000);
    EXPECT_TRUE(r.passed());
    ASSERT_FALSE(r.rows.empty());
    EXPECT_EQ(r.rows[0].items, 50000u);  // the global pass emits every photon asked for
}

TEST_P(PhotonCheck, TraceMatchesTheTwin) {
    PhotonCheckReport r = run(GetParam(), "trace", 20000);
    EXPECT_TRUE(r.passed());
    ASSERT_FALSE(r.rows.empty());
    EXPECT_EQ(r.rows[0].items, 20000u);
    EXPECT_GT(r.rows[0].hostDeposits, 5000u) << "too few deposits for the check to mean much";
    // Caustic paths exist when a light reaches a specular surface; every shipped scene's
    // specular surfaces (cornell-glossy's mixed floor included) send LS+D photons somewhere.
    ASSERT_EQ(r.rows.size(), 2u);
    EXPECT_EQ(r.rows[1].pass, "caustic");
    if (r.rows[1].items > 0) {
        EXPECT_GT(r.rows[1].hostDeposits, 0u) << "an empty caustic map checks nothing";
    }
}

TEST_P(PhotonCheck, DepositMatchesTheTwinByteForByte) {
    PhotonCheckReport r = run(GetParam(), "deposit", 20000);
    EXPECT_TRUE(r.passed());
    ASSERT_FALSE(r.rows.empty());
    for (const auto& row : r.rows) {
        EXPECT_EQ(row.byteMismatches, 0u) << row.pass;
        EXPECT_EQ(row.hostDeposits, row.deviceDeposits) << row.pass;
        if (row.hostDeposits > 4) {
            EXPECT_GT(row.growths, 0u) << row.pass << ": the small map must have grown";
        }
    }
}

// The whole pass both ways: pipeline/photon_pass in several device batches against the twin's
// one batch, maps aligned path by path.
TEST_P(PhotonCheck, WholePassMatchesTheTwin) {
    PhotonCheckReport r = run(GetParam(), "pass", 10000);
    EXPECT_TRUE(r.passed());
    ASSERT_EQ(r.rows.size(), 2u);
    EXPECT_EQ(r.rows[0].items, 10000u);
    EXPECT_GE(r.rows[0].deviceBatches, 3u);
    // Records agree to the byte until a last-bit difference (sphere hits: sqrt, division) enters a
    // path; it then stays within the check's tolerances. Long walks drift most: the 0.8 furnace
    // (five bounces a path on average) keeps 41 % of its records byte-identical, the other shipped
    // scenes 57–80 %.
    EXPECT_GT(r.rows[0].identicalRecords, r.rows[0].hostDeposits / 3) << "many records should agree to the byte";
}

INSTANTIATE_TEST_SUITE_P(ShippedScenes, PhotonCheck, ::testing::ValuesIn(shippedScenes()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             std::string name = std::filesystem::path(info.param).stem().string();
                             for (char& c : name)
                                 if (!isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name;
                         });

// A check that cannot fail is a defect: corrupt the device's answers and watch each stage fail.
TEST(PhotonCheckFails, OnCorruptedDeviceResults) {
    const Prepared& p = prepared(std::string(PHOTONCL_SOURCE_DIR) + "/scenes/cornell-box.json");
    const uint32_t n = 2000;
    std::vector<uint32_t> first = referenceLightFirstPhoton(p.buffers, PCL_PASS_GLOBAL, n);
    PclPhotonParams params = referencePhotonParams(p.buffers, p.geometry, 9, PCL_PASS_GLOBAL, 0, n, 16);
    const float radius = p.buffers.sceneRadius;

    std::vector<PclPhotonRay> twinRays = emitPhotonsReference(p.buffers, first, params);
    std::vector<PclPhotonRay> devRays = emitOnDevice(test::testDevice(), p.geometry, p.buffers, first, params);
    PhotonCheckReport emit;
    emit.stage = "emit";
    emit.rows.emplace_back();
    comparePhotonRays(twinRays, devRays, radius, emit.rows[0]);
    EXPECT_TRUE(emit.passed());
    devRays[17].dx += 1e-3f;  // one direction off by 1e-3
    emit.rows[0] = {};
    comparePhotonRays(twinRays, devRays, radius, emit.rows[0]);
    EXPECT_FALSE(emit.passed());
    EXPECT_EQ(emit.rows[0].directionMismatches, 1u);

    ReferencePhotonBatch twin = tracePhotonsReference(p.buffers, p.geometry, params, twinRays);
    PhotonTraceResult dev = tracePhotonsOnDevice(test::testDevice(), p.geometry, p.buffers, twinRays, params);
    PhotonCheckReport trace;
    trace.stage = "trace";
    trace.rows.emplace_back();
    comparePhotonPaths(twin, dev, radius, trace.rows[0]);
    EXPECT_TRUE(trace.passed());
    // Flip the flags of the first deposit in 3 paths of 2000 (0.15 %): divergent, fails.
    int flipped = 0;
    for (uint32_t i = 0; i < n && flipped < 3; ++i)
        if (dev.counts[i] > 0) {
            dev.slots[size_t(i) * dev.slotsPerPath].packed ^= PCL_PHOTON_AFTER_SPECULAR;
            ++flipped;
        }
    trace.rows[0] = {};
    comparePhotonPaths(twin, dev, radius, trace.rows[0]);
    EXPECT_EQ(trace.rows[0].packedMismatches, 3u);
    EXPECT_FALSE(trace.passed());

    std::vector<PclPhoton> map = depositOnDevice(test::testDevice(), twin.counts, twin.slots, twin.slotsPerPath);
    std::vector<PclPhoton> twinMap;
    depositPhotonsReference(twin.counts, twin.slots, twin.slotsPerPath, twinMap);
    PhotonCheckReport deposit;
    deposit.stage = "deposit";
    deposit.rows.emplace_back();
    comparePhotonMaps(twinMap, map, deposit.rows[0]);
    EXPECT_TRUE(deposit.passed());
    ASSERT_GT(map.size(), 10u);
    std::swap(map[3], map[4]);  // order matters
    deposit.rows[0] = {};
    comparePhotonMaps(twinMap, map, deposit.rows[0]);
    EXPECT_EQ(deposit.rows[0].byteMismatches, 2u);
    EXPECT_FALSE(deposit.passed());
}

}  // namespace
}  // namespace pcl
