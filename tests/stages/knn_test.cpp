// k nearest neighbours on the device (kernels/knn.cl, pipeline/knn) through the kd-tree and the
// hash grid, against the brute force (reference/knn): the same neighbour count, the same photon
// indices in the same order, squared distances within 1e-6 relative (they are computed the same
// way, so in practice equal), r² ≤ r_max². On 10 000 random queries, on surface points of
// shipped scenes (through checkKnn), for k = 1, 50, 500, and on degenerate maps.
//
// The kd-trees searched here are built by a small host helper written from kernels/README.md
// ("kd-tree"), so the search is tested whatever builds trees elsewhere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <tuple>
#include <vector>

#include "check/knn.h"
#include "check/on_device.h"
#include "device_fixture.h"
#include "pipeline/kdtree.h"
#include "pipeline/knn.h"
#include "reference/knn.h"
#include "scene/load_scene.h"

namespace pcl {
namespace {

PclPhoton photonAt(float x, float y, float z) {
    PclPhoton p{};
    p.x = x, p.y = y, p.z = z;
    p.packed = 0x00010203u;  // bits the tree must keep (only the axis bits change)
    return p;
}

// ---- Left-balanced kd-tree from the spec (test helper) ----------------------------------
uint32_t orderKey(float f) {
    uint32_t b;
    std::memcpy(&b, &f, 4);
    return b & 0x80000000u ? ~b : b | 0x80000000u;
}

struct TestTree {
    std::vector<PclPhoton> nodes;
    std::vector<uint32_t> index;
};

void place(const std::vector<PclPhoton>& map, std::vector<uint32_t> ids, size_t slot, TestTree& t) {
    const size_t n = ids.size();
    if (n == 0) return;
    float lo[3], hi[3];
    for (int a = 0; a < 3; ++a) lo[a] = INFINITY, hi[a] = -INFINITY;
    for (uint32_t id : ids) {
        const float c[3] = {map[id].x, map[id].y, map[id].z};
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
    }
    const float ext[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    const int axis = ext[0] >= ext[1] && ext[0] >= ext[2] ? 0 : (ext[1] >= ext[2] ? 1 : 2);
    auto c = [&](uint32_t id) { return axis == 0 ? map[id].x : axis == 1 ? map[id].y : map[id].z; };
    std::sort(ids.begin(), ids.end(), [&](uint32_t a, uint32_t b) {
        return orderKey(c(a)) < orderKey(c(b)) || (orderKey(c(a)) == orderKey(c(b)) && a < b);
    });
    size_t left = 0;
    if (n > 1) {
        size_t h = 0;
        while ((size_t(1) << (h + 1)) <= n) ++h;
        const size_t half = size_t(1) << (h - 1);
        left = half - 1 + std::min(half, n - ((size_t(1) << h) - 1));
    }
    t.nodes[slot] = map[ids[left]];
    t.nodes[slot].packed = (t.nodes[slot].packed & ~PCL_PHOTON_AXIS_MASK) | uint32_t(axis) << PCL_PHOTON_AXIS_SHIFT;
    t.index[slot] = ids[left];
    place(map, std::vector<uint32_t>(ids.begin(), ids.begin() + left), 2 * slot + 1, t);
    place(map, std::vector<uint32_t>(ids.begin() + left + 1, ids.end()), 2 * slot + 2, t);
}

TestTree buildTestTree(const std::vector<PclPhoton>& map) {
    TestTree t{std::vector<PclPhoton>(map.size()), std::vector<uint32_t>(map.size(), PCL_NO_HIT)};
    std::vector<uint32_t> ids(map.size());
    for (size_t i = 0; i < ids.size(); ++i) ids[i] = uint32_t(i);
    place(map, ids, 0, t);
    return t;
}

// ---- Comparison -------------------------------------------------------------------------
KnnResult search(KnnStructure s, const std::vector<PclPhoton>& map, const TestTree& tree,
                 const std::vector<PclKnnQuery>& qs) {
    if (s == KnnStructure::KdTree) return knnKdTreeOnDevice(test::testDevice(), tree.nodes, tree.index, qs);
    return knnHashGridOnDevice(test::testDevice(), map, qs);
}

// Every structure, every k, against one brute force at the largest k.
std::vector<KnnCheckRow> expectBruteForce(const std::vector<PclPhoton>& map, std::vector<PclKnnQuery> qs,
                                          std::vector<uint32_t> ks = {1, 50, 500}) {
    const TestTree tree = buildTestTree(map);
    for (auto& q : qs) q.k = PCL_KNN_MAX_K;
    const ReferenceKnn brute = referenceKnnBruteForce(map, qs);
    std::vector<KnnCheckRow> rows;
    for (KnnStructure s : {KnnStructure::KdTree, KnnStructure::HashGrid})
        for (uint32_t k : ks) {
            for (auto& q : qs) q.k = k;
            KnnCheckRow row;
            row.k = k;
            row.structure = knnStructureName(s);
            compareKnn(qs, brute, search(s, map, tree, qs), row);
            EXPECT_TRUE(row.passed()) << row.structure << " k=" << k << ": count!= " << row.countMismatches
                                      << " index!= " << row.indexMismatches << " r2 bad " << row.radiusViolations
                                      << " d2 err " << row.maxDist2Error;
            rows.push_back(row);
        }
    return rows;
}

PclKnnQuery query(float x, float y, float z, float maxRadius2, uint32_t k = 50) {
    PclKnnQuery q{};
    q.x = x, q.y = y, q.z = z, q.maxRadius2 = maxRadius2, q.k = k;
    return q;
}

std::vector<PclPhoton> uniformMap(size_t n, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclPhoton> m(n);
    for (auto& p : m) p = photonAt(u(rng), u(rng), u(rng));
    return m;
}

TEST(Knn, TestTreeIsLeftBalancedAndSplitsCorrectly) {
    const std::vector<PclPhoton> map = uniformMap(1000, 3);
    const TestTree t = buildTestTree(map);
    std::vector<uint32_t> sorted = t.index;
    std::sort(sorted.begin(), sorted.end());
    for (uint32_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i);  // a permutation: every slot filled
    for (size_t i = 0; i < t.nodes.size(); ++i) {
        const uint32_t axis = (t.nodes[i].packed & PCL_PHOTON_AXIS_MASK) >> PCL_PHOTON_AXIS_SHIFT;
        const float* split = &t.nodes[i].x;
        for (size_t c : {2 * i + 1, 2 * i + 2})
            if (c < t.nodes.size()) {
                const float v = (&t.nodes[c].x)[axis];
                if (c == 2 * i + 1) {
                    EXPECT_LE(v, split[axis]);
                } else EXPECT_GE(v, split[axis]);
            }
    }
    // The same tree as the device build that knnOnDevice searches (pipeline/kdtree).
    const KdTree dev = buildKdTreeOnDevice(test::testDevice(), map);
    EXPECT_EQ(dev.index, t.index);
    ASSERT_EQ(dev.photons.size(), t.nodes.size());
    EXPECT_EQ(std::memcmp(dev.photons.data(), t.nodes.data(), t.nodes.size() * sizeof(PclPhoton)), 0);
}

TEST(Knn, TenThousandRandomQueriesMatchBruteForce) {
    const std::vector<PclPhoton> map = uniformMap(20000, 1);
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<float> u(-0.1f, 1.1f), r(0.25f, 1.0f);
    std::vector<PclKnnQuery> qs;
    const float rMax = 0.15f;  // ~280 photons inside r_max: k = 50 fills, k = 500 is cut by the radius
    for (int i = 0; i < 10000; ++i) qs.push_back(query(u(rng), u(rng), u(rng), r(rng) * rMax * rMax));
    const auto rows = expectBruteForce(map, qs);
    // The set exercises both limits: full heaps (k = 50) and radius-limited ones (k = 500).
    size_t full50 = 0, cut500 = 0;
    for (const auto& row : rows) {
        if (row.k == 50) full50 = row.neighbours;
        if (row.k == 500) cut500 = row.neighbours;
    }
    EXPECT_GT(full50, 10000u * 30);
    EXPECT_LT(cut500, 10000u * 400);
    EXPECT_GT(cut500, full50);
}

TEST(Knn, QueriesWithDifferentKInOneLaunch) {
    const std::vector<PclPhoton> map = uniformMap(5000, 4);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::uniform_int_distribution<uint32_t> k(1, PCL_KNN_MAX_K);
    std::vector<PclKnnQuery> qs;
    for (int i = 0; i < 2000; ++i) qs.push_back(query(u(rng), u(rng), u(rng), 0.09f, k(rng)));
    const ReferenceKnn brute = referenceKnnBruteForce(map, qs);
    const TestTree tree = buildTestTree(map);
    for (KnnStructure s : {KnnStructure::KdTree, KnnStructure::HashGrid}) {
        KnnCheckRow row;
        const KnnResult r = search(s, map, tree, qs);
        EXPECT_EQ(r.stride, brute.stride);
        compareKnn(qs, brute, r, row);
        EXPECT_TRUE(row.passed()) << knnStructureName(s);
        // The same through knnOnDevice, which builds the structure on the device itself.
        KnnCheckRow whole;
        compareKnn(qs, brute, knnOnDevice(test::testDevice(), map, s, qs), whole);
        EXPECT_TRUE(whole.passed()) << "knnOnDevice " << knnStructureName(s);
    }
}

TEST(Knn, NothingWithinRadiusReturnsZero) {
    const std::vector<PclPhoton> map = uniformMap(3000, 6);
    const TestTree tree = buildTestTree(map);
    const std::vector<PclKnnQuery> qs = {query(5, 5, 5, 0.25f, 500), query(-2, 0.5f, 0.5f, 1.0f, 1),
                                         query(0.5f, 0.5f, 0.5f, 0.0f, 10)};
    for (KnnStructure s : {KnnStructure::KdTree, KnnStructure::HashGrid}) {
        const KnnResult r = search(s, map, tree, qs);
        for (size_t q = 0; q < qs.size(); ++q) {
            EXPECT_EQ(r.counts[q], 0u) << knnStructureName(s) << " query " << q;
            EXPECT_EQ(r.radius2[q], 0.0f);
            EXPECT_LE(r.radius2[q], qs[q].maxRadius2);
            for (uint32_t j = 0; j < r.stride; ++j) EXPECT_EQ(r.indices[q * r.stride + j], PCL_NO_HIT);
        }
    }
    // maxRadius2 = 0 is an empty query (kernels/knn.cl), even exactly at a photon: the eye
    // estimate's records with nothing to estimate cost no search; a tiny radius there finds it.
    for (float r2 : {0.0f, 1e-12f}) {
        const std::vector<PclKnnQuery> at = {query(map[17].x, map[17].y, map[17].z, r2, 5)};
        const ReferenceKnn twin = referenceKnnBruteForce(map, at);
        for (KnnStructure s : {KnnStructure::KdTree, KnnStructure::HashGrid}) {
            const KnnResult r = search(s, map, tree, at);
            ASSERT_EQ(r.counts[0], r2 > 0.0f ? 1u : 0u) << knnStructureName(s) << " r2 " << r2;
            EXPECT_EQ(r.counts[0], twin.counts[0]);
            if (r2 > 0.0f) {
                EXPECT_EQ(r.indices[0], 17u);
                EXPECT_EQ(r.dist2[0], 0.0f);
            }
        }
    }
}

TEST(Knn, IdenticalPhotonsTieByIndex) {
    const std::vector<PclPhoton> map(50000, photonAt(1.0f, 2.0f, 3.0f));
    const std::vector<PclKnnQuery> qs = {query(1, 2, 3, 0.01f), query(1.05f, 2, 3, 0.01f), query(1.2f, 2, 3, 0.01f)};
    expectBruteForce(map, qs);
    const TestTree tree = buildTestTree(map);
    std::vector<PclKnnQuery> q500 = qs;
    for (auto& q : q500) q.k = 500;
    for (KnnStructure s : {KnnStructure::KdTree, KnnStructure::HashGrid}) {
        const KnnResult r = search(s, map, tree, q500);
        ASSERT_EQ(r.counts[0], 500u);
        ASSERT_EQ(r.counts[1], 500u);
        EXPECT_EQ(r.counts[2], 0u);
        for (uint32_t j = 0; j < 500; ++j) {
            ASSERT_EQ(r.indices[j], j) << knnStructureName(s);  // the lowest indices, ascending
            ASSERT_EQ(r.indices[500 + j], j);
        }
    }
}

TEST(Knn, ClustersCollinearAndTinyMaps) {
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<float> u(0.0f, 1e-3f), v(-0.01f, 0.01f);
    std::vector<PclPhoton> clusters;
    for (int i = 0; i < 20000; ++i) {
        const float c = i % 2 ? 5.0f : 0.0f;
        clusters.push_back(photonAt(c + u(rng), c + u(rng), c + u(rng)));
    }
    std::vector<PclKnnQuery> qs;
    for (int i = 0; i < 300; ++i) {
        const float c = i % 3 == 0 ? 0.0f : i % 3 == 1 ? 5.0f : 2.5f;
        qs.push_back(query(c + v(rng), c + v(rng), c + v(rng), 4e-4f));
    }
    expectBruteForce(clusters, qs);

    std::vector<PclPhoton> line;
    for (int i = 0; i < 10000; ++i) line.push_back(photonAt(0.01f * i, 0.5f, -0.02f * i));
    qs.clear();
    for (int i = 0; i < 500; ++i) {
        const float t = 0.2f * i;
        qs.push_back(query(t + v(rng), 0.5f + v(rng), -2.0f * t + v(rng), 0.04f));
    }
    expectBruteForce(line, qs);

    const std::vector<PclKnnQuery> few = {query(0, 0, 0, 1.0f), query(0.5f, 0, 0, 0.1f), query(9, 9, 9, 1.0f)};
    expectBruteForce({}, few);
    expectBruteForce({photonAt(0.1f, 0, 0)}, few);
    const KnnResult one = knnHashGridOnDevice(test::testDevice(), {photonAt(0.1f, 0, 0)}, few);
    EXPECT_EQ(one.counts, (std::vector<uint32_t>{1, 0, 0}));
    EXPECT_EQ(one.indices[0], 0u);
}

TEST(Knn, HugeCoordinatesAndTinyRadii) {
    // Coordinates up to 1e7 (float spacing 1) with radii far below it: cell coordinates clamp
    // to ±1e9 and only coincident photons are found; and a map far from the origin with a
    // moderate radius, where the cell bounds carry rounding.
    std::mt19937_64 rng(12);
    std::uniform_int_distribution<int> lattice(-20, 20);
    std::vector<PclPhoton> far;
    for (int i = 0; i < 3000; ++i)
        far.push_back(photonAt(5e5f * lattice(rng), 5e5f * lattice(rng), 5e5f * lattice(rng)));
    std::vector<PclKnnQuery> qs;
    for (int i = 0; i < 300; ++i) qs.push_back(query(far[i * 7].x, far[i * 7].y, far[i * 7].z, 1e-6f));
    expectBruteForce(far, qs, {1, 50});
    std::uniform_real_distribution<float> u(0.0f, 100.0f);
    std::vector<PclPhoton> offset;
    for (int i = 0; i < 20000; ++i) offset.push_back(photonAt(1e6f + u(rng), -3e6f + u(rng), 2e6f + u(rng)));
    qs.clear();
    for (int i = 0; i < 500; ++i) qs.push_back(query(1e6f + u(rng), -3e6f + u(rng), 2e6f + u(rng), 36.0f));
    expectBruteForce(offset, qs, {1, 50});
}

TEST(Knn, RejectsBadQueries) {
    const std::vector<PclPhoton> map = uniformMap(10, 1);
    EXPECT_THROW(knnHashGridOnDevice(test::testDevice(), map, {query(0, 0, 0, 1.0f, 0)}), InternalError);
    EXPECT_THROW(knnHashGridOnDevice(test::testDevice(), map, {query(0, 0, 0, 1.0f, 501)}), InternalError);
    EXPECT_THROW(knnHashGridOnDevice(test::testDevice(), map, {query(0, 0, 0, INFINITY, 5)}), InternalError);
    EXPECT_THROW(knnHashGridOnDevice(test::testDevice(), map, {query(0, 0, 0, -1.0f, 5)}), InternalError);
}

// Real surface points of shipped scenes, on their own photon maps (global and caustic).
TEST(Knn, ShippedScenesSurfaceAndRandomQueries) {
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(PHOTONCL_SOURCE_DIR) / "scenes"))
        if (e.path().extension() == ".json") files.push_back(e.path());
#ifdef PHOTONCL_HAVE_GLTF  // the build for the GPU machine reads no glTF
        else if (e.path().extension() == ".gltf") files.push_back(e.path());
#endif
    std::sort(files.begin(), files.end());
    ASSERT_GE(files.size(), 2u);
    size_t causticRows = 0;
    for (const auto& file : files) {
        const std::string name = file.filename().string();
        SCOPED_TRACE(name);
        const Scene scene = loadScene(file.string());
        KnnCheckOptions o;
        // Under a sky most photons cross the disc around the scene and leave it (sky-spheres stores
        // about a third): 4× the photons give its surfaces a density like the closed rooms'.
        o.photons = scene.environment.active() ? 40000 : 10000;
        o.randomQueries = 1000;
        o.surfaceQueries = 2000;
        const KnnCheckReport report = checkKnn(test::testDevice(), scene, o);
        std::printf("%s\n%s", name.c_str(), report.table().c_str());
        EXPECT_TRUE(report.passed());
        EXPECT_EQ(report.rows.size(), 2u * 2u * 2u * 3u);
        size_t surfaceNeighbours = 0;
        for (const auto& r : report.rows)
            if (r.queries == "surface" && r.map == "global" && r.k == 50) surfaceNeighbours += r.neighbours;
        EXPECT_GT(surfaceNeighbours, 2u * 1000u * 50u);  // both structures: most surface queries find 50
        for (const auto& r : report.rows) causticRows += r.map == "caustic" && r.neighbours > 0;
    }
    EXPECT_GT(causticRows, 0u);  // some scene's caustic map is searched too
}

}  // namespace
}  // namespace pcl

namespace pcl {
namespace {

// The first search bound (knnSearchKdTree's firstRadius2) changes only the speed: a bound far
// too small (every query searches again), about right (most succeed at once) and none give the
// same counts, indices and distances bit for bit; the mean-density guess is what the renderer uses.
TEST(Knn, FirstSearchBoundGivesTheSameNeighbours) {
    Device& device = test::testDevice();
    const std::vector<PclPhoton> map = uniformMap(20000, 7);
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<float> u(-0.1f, 1.1f);
    std::vector<PclKnnQuery> qs;
    for (int i = 0; i < 4096; ++i) qs.push_back(query(u(rng), u(rng), u(rng), 0.04f, i % 3 ? 50u : 8u));
    const KnnKdTree tree = packKdTree(device, buildKdTree(device, device.upload(map), map.size()));
    const cl::Buffer qb = device.upload(qs);
    auto run = [&](float first) {
        DeviceKnnOutput out;
        knnSearchKdTree(device, tree, qb, qs.size(), 50, out, first);
        return std::make_tuple(
            device.download<uint32_t>(out.counts, qs.size()), device.download<uint32_t>(out.indices, qs.size() * 50),
            device.download<float>(out.dist2, qs.size() * 50), device.download<float>(out.radius2, qs.size()));
    };
    const auto none = run(INFINITY);
    // Volume density 20000 per unit cube: k = 50 lies within r² ≈ 0.0071; 1e-6 is far too small.
    for (float first : {1e-6f, 0.004f, 0.0071f, 0.02f, firstSearchRadius2(map.size(), 50, 6.0)})
        EXPECT_TRUE(run(first) == none) << "firstRadius2 " << first;
    DeviceKnnOutput out;
    EXPECT_THROW(knnSearchKdTree(device, tree, qb, qs.size(), 50, out, -1.0f), InternalError);
    EXPECT_THROW(knnSearchKdTree(device, tree, qb, qs.size(), 50, out, NAN), InternalError);
    EXPECT_EQ(firstSearchRadius2(0, 50, 1.0), INFINITY);
    EXPECT_NEAR(firstSearchRadius2(1000, 50, 2.0), 9.0 * 50 * 2.0 / (3.14159265 * 1000), 1e-6);
}

}  // namespace
}  // namespace pcl
