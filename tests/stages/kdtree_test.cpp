// kdtree_* (kernels/kdtree.cl) against the twin (host/reference/kdtree): the device tree equals
// the twin's byte for byte (photons with axis bits, and the heap → photon index permutation) on
// real maps of the shipped scenes and on random points; every tree is a valid left-balanced
// kd-tree (a permutation of the input; each node's split axis the largest extent of its
// subtree's box; every left-subtree photon ≤ node ≤ every right-subtree photon on the node's
// axis, ordered by (coordinate key, photon index)); degenerate maps (0 and 1 photon, 1M
// identical photons, two dense clusters, collinear photons) build in ⌊log2 n⌋ + 1 levels.
// Validity is judged by kdTreeDefect (check/maps), the check `photoncl check --stage
// build` runs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>

#include "check/maps.h"
#include "check/on_device.h"
#include "device_fixture.h"
#include "photon_test_scenes.h"
#include "pipeline/kdtree.h"
#include "reference/kdtree.h"

namespace pcl {
namespace {

PclPhoton photonAt(float x, float y, float z, uint32_t tag) {
    PclPhoton p;
    p.x = x;
    p.y = y;
    p.z = z;
    p.rgbe = tag * 2654435761u;
    p.packed = (tag & 0xFFFFFFu) | PCL_PHOTON_AXIS_MASK;  // stale axis bits must be overwritten
    return p;
}

uint32_t axisOf(const PclPhoton& p) { return (p.packed & PCL_PHOTON_AXIS_MASK) >> PCL_PHOTON_AXIS_SHIFT; }

void expectValidTree(const std::vector<PclPhoton>& in, const std::vector<PclPhoton>& tree,
                     const std::vector<uint32_t>& index) {
    EXPECT_EQ(kdTreeDefect(in, tree, index), "");
}

// finishSize: as buildKdTree's (-1 the device default; 0 every level by sorting; 5 a mix; 32 the
// GPU default).
void expectDeviceEqualsTwin(const std::vector<PclPhoton>& in, const char* what, bool validate = true,
                            int finishSize = -1) {
    SCOPED_TRACE(what);
    SCOPED_TRACE("finishSize " + std::to_string(finishSize));
    KdTree dev = buildKdTreeOnDevice(test::testDevice(), in, nullptr, finishSize);
    ReferenceKdTree ref = referenceBuildKdTree(in);
    ASSERT_EQ(dev.photons.size(), in.size());
    ASSERT_EQ(dev.index, ref.index);
    ASSERT_EQ(0, std::memcmp(dev.photons.data(), ref.photons.data(), in.size() * sizeof(PclPhoton)));
    if (validate) expectValidTree(in, dev.photons, dev.index);
}

TEST(KdTree, LeftSizeIsTheCompleteTreesLeftSubtree) {
    // Count the heap positions under child 1 of a complete tree of n nodes.
    for (uint32_t n = 1; n < 2000; ++n) {
        uint32_t left = 0;
        for (uint64_t first = 1, width = 1; first < n; first = 2 * first + 1, width *= 2)
            left += uint32_t(std::min<uint64_t>(width, n - first));
        ASSERT_EQ(referenceKdLeftSize(n), left) << n;
    }
}

// The validator is a check that can fail: swapped nodes, a wrong axis, a tie broken the wrong way.
TEST(KdTree, ValidatorCatchesBrokenTrees) {
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclPhoton> in;
    for (uint32_t i = 0; i < 1000; ++i) in.push_back(photonAt(u(rng), u(rng), u(rng), i));
    ReferenceKdTree t = referenceBuildKdTree(in);
    ASSERT_EQ(kdTreeDefect(in, t.photons, t.index), "");
    ReferenceKdTree swapped = t;
    std::swap(swapped.photons[1], swapped.photons[2]);
    std::swap(swapped.index[1], swapped.index[2]);
    EXPECT_NE(kdTreeDefect(in, swapped.photons, swapped.index), "");
    ReferenceKdTree axis = t;
    axis.photons[0].packed ^= 1u << PCL_PHOTON_AXIS_SHIFT;
    EXPECT_NE(kdTreeDefect(in, axis.photons, axis.index), "");
    // Two identical photons: the lower index must be on the left.
    std::vector<PclPhoton> two = {photonAt(1, 1, 1, 0), photonAt(1, 1, 1, 1)};
    ReferenceKdTree t2 = referenceBuildKdTree(two);
    EXPECT_EQ(t2.index, (std::vector<uint32_t>{1, 0}));
    EXPECT_EQ(kdTreeDefect(two, t2.photons, t2.index), "");
    std::swap(t2.photons[0], t2.photons[1]);
    std::swap(t2.index[0], t2.index[1]);
    EXPECT_NE(kdTreeDefect(two, t2.photons, t2.index), "");
}

TEST(KdTree, RandomPointsMatchTwin) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-10.0f, 10.0f);
    for (size_t n : {2, 3, 4, 5, 7, 8, 9, 100, 255, 256, 257, 4097, 50000}) {
        std::vector<PclPhoton> in;
        for (size_t i = 0; i < n; ++i) in.push_back(photonAt(u(rng), 0.3f * u(rng), 2.0f * u(rng), uint32_t(i)));
        for (int finish : {-1, 0, 5, 32})
            expectDeviceEqualsTwin(in, ("random n = " + std::to_string(n)).c_str(), true, finish);
    }
    // Coarse coordinates: many ties on every axis, broken by the photon index.
    std::vector<PclPhoton> in;
    std::uniform_int_distribution<int> g(-3, 3);
    for (uint32_t i = 0; i < 30000; ++i) in.push_back(photonAt(float(g(rng)), float(g(rng)), -0.0f * float(g(rng)), i));
    for (int finish : {-1, 0}) expectDeviceEqualsTwin(in, "lattice with ties and signed zeros", true, finish);
}

TEST(KdTree, EmptyAndSinglePhoton) {
    KdTree empty = buildKdTreeOnDevice(test::testDevice(), {});
    EXPECT_TRUE(empty.photons.empty());
    EXPECT_TRUE(referenceBuildKdTree({}).photons.empty());
    std::vector<PclPhoton> one = {photonAt(1, 2, 3, 7)};
    expectDeviceEqualsTwin(one, "one photon");
    KdTree t = buildKdTreeOnDevice(test::testDevice(), one);
    EXPECT_EQ(axisOf(t.photons[0]), 0u);
    EXPECT_EQ(t.index[0], 0u);
}

// 1M photons at one point (with the default finish: levels split a level at a time, then
// kdtree_finish): every comparison is a tie broken by index; the build is still ⌊log2 n⌋ + 1
// levels of linear work each, not a quadratic partition.
TEST(KdTree, MillionIdenticalPhotons) {
    const size_t n = 1000000;
    std::vector<PclPhoton> in(n);
    for (size_t i = 0; i < n; ++i) in[i] = photonAt(0.5f, -1.25f, 3.0f, uint32_t(i));
    cl::Buffer buf = test::testDevice().upload(in);
    DeviceKdTree t = buildKdTree(test::testDevice(), buf, n);
    EXPECT_EQ(t.levels, 20u);  // ⌊log2 1e6⌋ + 1
    EXPECT_LE(t.sortedLevels, 20u);
    std::vector<uint32_t> index = test::testDevice().download<uint32_t>(t.index, n);
    ReferenceKdTree ref = referenceBuildKdTree(in);
    ASSERT_EQ(index, ref.index);
    std::vector<PclPhoton> photons = test::testDevice().download<PclPhoton>(t.photons, n);
    ASSERT_EQ(0, std::memcmp(photons.data(), ref.photons.data(), n * sizeof(PclPhoton)));
    // All identical, so the tree is the index order laid out by the tie rule alone: an in-order
    // walk visits photons 0, 1, 2, ...
    std::vector<uint32_t> inorder;
    std::vector<size_t> stack;
    size_t h = 0;
    while (h < n || !stack.empty()) {
        while (h < n) {
            stack.push_back(h);
            h = 2 * h + 1;
        }
        h = stack.back();
        stack.pop_back();
        inorder.push_back(index[h]);
        h = 2 * h + 2;
    }
    for (size_t i = 0; i < n; ++i) ASSERT_EQ(inorder[i], i);
    for (const PclPhoton& p : photons) ASSERT_EQ(axisOf(p), 0u);
}

TEST(KdTree, DenseClustersAndCollinearPhotons) {
    std::mt19937 rng(4);
    std::normal_distribution<float> tiny(0.0f, 1e-6f);
    std::vector<PclPhoton> clusters;
    for (uint32_t i = 0; i < 200000; ++i) {
        const float c = (i & 1) ? 1000.0f : -1000.0f;
        clusters.push_back(photonAt(c + tiny(rng), 5.0f + tiny(rng), c * 0.5f + tiny(rng), i));
    }
    expectDeviceEqualsTwin(clusters, "two dense clusters");
    std::vector<PclPhoton> line;
    std::uniform_real_distribution<float> t(0.0f, 1.0f);
    for (uint32_t i = 0; i < 100000; ++i) {
        const float s = (i % 7 == 0) ? 0.25f : t(rng);  // and repeated points on the line
        line.push_back(photonAt(1.0f, 2.0f - s, 3.0f, i));
    }
    for (int finish : {-1, 0}) expectDeviceEqualsTwin(line, "collinear along y", true, finish);
    std::vector<PclPhoton> diagonal;
    for (uint32_t i = 0; i < 4096; ++i) {
        const float s = float(i % 1000);
        diagonal.push_back(photonAt(s, s, s, i));  // equal extents: ties go to x
    }
    expectDeviceEqualsTwin(diagonal, "collinear along the diagonal");
}

TEST(KdTree, ShippedSceneMapsMatchTwin) {
    const std::filesystem::path dir = std::filesystem::path(PHOTONCL_SOURCE_DIR) / "scenes";
    size_t scenes = 0;
    for (const char* file : {"cornell-box.json", "cornell-spheres.json", "cornell-glossy.json", "gltf-room.gltf"}) {
        const std::filesystem::path path = dir / file;
#ifndef PHOTONCL_HAVE_GLTF
        if (path.extension() == ".gltf") continue;
#endif
        const PhotonMaps maps = test::runScenePhotonPass(path.string(), 20000, 3).maps;
        ASSERT_GT(maps.global.size(), 1000u) << file;
        for (int finish : {-1, 0})
            expectDeviceEqualsTwin(maps.global, (std::string(file) + " global").c_str(), true, finish);
        if (!maps.caustic.empty()) expectDeviceEqualsTwin(maps.caustic, (std::string(file) + " caustic").c_str());
        ++scenes;
    }
    EXPECT_GE(scenes, 3u);
}

}  // namespace
}  // namespace pcl
