// sort_histogram / sort_scan / sort_scatter / sort_buckets (kernels/sort.cl): the device radix
// sort equals std::stable_sort (host/reference/sort) bit for bit — keys and the values that
// travel with them, so stability is checked too — on random, sorted, reversed, all-equal,
// few-distinct and alternate-byte keys (digits constant in some passes) of 32 and 64 bits, at
// sizes around the tile edges (CPU 16384, GPU 4096) and 256 up to 1M (bucketed on the CPU from
// 2^18 pairs, all-equal keys taking the plain passes), and once at 10M; sortBits ignores the
// bits above it; the float → key flip orders floats.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include <stdlib.h>

#include "check/on_device.h"
#include "device_fixture.h"
#include "pipeline/sort.h"
#include "reference/sort.h"

namespace pcl {
namespace {

enum class Pattern { Random, Sorted, Reversed, AllEqual, FewDistinct, AlternateBytes };
const char* name(Pattern p) {
    switch (p) {
        case Pattern::Random: return "random";
        case Pattern::Sorted: return "sorted";
        case Pattern::Reversed: return "reversed";
        case Pattern::AllEqual: return "all-equal";
        case Pattern::AlternateBytes: return "alternate-bytes";
        default: return "few-distinct";
    }
}

template <class K>
std::vector<K> makeKeys(size_t n, Pattern p, uint32_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<K> k(n);
    switch (p) {
        case Pattern::Random:
            for (K& x : k) x = K(rng());
            break;
        case Pattern::Sorted:
        case Pattern::Reversed:
            for (K& x : k) x = K(rng());
            std::sort(k.begin(), k.end());
            if (p == Pattern::Reversed) std::reverse(k.begin(), k.end());
            break;
        case Pattern::AllEqual: std::fill(k.begin(), k.end(), K(rng())); break;
        case Pattern::AlternateBytes:  // every other byte zero: passes whose digit is constant
            for (K& x : k) x = K(rng() & 0xFF00FF00FF00FF00ull);
            break;
        case Pattern::FewDistinct: {
            K pool[5];
            for (K& x : pool) x = K(rng());
            for (K& x : k) x = pool[rng() % 5];
            break;
        }
    }
    return k;
}

// Values: the input position scrambled a little, so a wrong pairing cannot pass as a right one.
std::vector<uint32_t> makeValues(size_t n) {
    std::vector<uint32_t> v(n);
    for (size_t i = 0; i < n; ++i) v[i] = uint32_t(i * 2654435761u);
    return v;
}

template <class K>
void expectSortMatches(size_t n, Pattern p, uint32_t seed, int sortBits = 8 * sizeof(K)) {
    std::vector<K> keys = makeKeys<K>(n, p, seed);
    std::vector<uint32_t> values = makeValues(n);
    std::vector<K> wantKeys = keys;
    std::vector<uint32_t> wantValues = values;
    referenceSortPairs(wantKeys, wantValues, sortBits);
    Device& dev = test::testDevice();
    cl::Buffer kb = dev.upload(keys, CL_MEM_READ_WRITE), vb = dev.upload(values, CL_MEM_READ_WRITE);
    sortPairsOnDevice(dev, kb, vb, n, int(8 * sizeof(K)), sortBits);
    std::vector<K> gotKeys = dev.download<K>(kb, n);
    std::vector<uint32_t> gotValues = dev.download<uint32_t>(vb, n);
    size_t firstKey = std::mismatch(gotKeys.begin(), gotKeys.end(), wantKeys.begin()).first - gotKeys.begin();
    size_t firstValue = std::mismatch(gotValues.begin(), gotValues.end(), wantValues.begin()).first - gotValues.begin();
    EXPECT_EQ(firstKey, n) << 8 * sizeof(K) << "-bit " << name(p) << " n = " << n << ": first key mismatch";
    EXPECT_EQ(firstValue, n) << 8 * sizeof(K) << "-bit " << name(p) << " n = " << n << ": first value mismatch";
}

const Pattern kPatterns[] = {Pattern::Random,   Pattern::Sorted,      Pattern::Reversed,
                             Pattern::AllEqual, Pattern::FewDistinct, Pattern::AlternateBytes};
const size_t kSizes[] = {1, 2, 3, 255, 256, 257, 1000, 4095, 4096, 4097, 16383, 16384, 16385, 65537, 1000000};

TEST(Sort, Keys32MatchStdStableSort) {
    uint32_t seed = 1;
    for (size_t n : kSizes)
        for (Pattern p : kPatterns) expectSortMatches<uint32_t>(n, p, seed++);
}

TEST(Sort, Keys64MatchStdStableSort) {
    uint32_t seed = 100;
    for (size_t n : kSizes)
        for (Pattern p : kPatterns) expectSortMatches<uint64_t>(n, p, seed++);
}

// sortBits: only the low bits order the pairs (the kd-tree build sorts 32 + ⌈log2 levels⌉ bits);
// the high bits are random, so sorting by them too would give a different order.
TEST(Sort, SortBitsIgnoresHigherBits) {
    for (int bits : {1, 5, 36, 47})
        for (Pattern p : {Pattern::Random, Pattern::FewDistinct}) expectSortMatches<uint64_t>(70001, p, 7 + bits, bits);
    for (int bits : {3, 20}) expectSortMatches<uint32_t>(70001, Pattern::Random, 11 + bits, bits);
    // large enough for the CPU's bucketed sort (top digit = the highest sorted bits)
    expectSortMatches<uint64_t>(300000, Pattern::Random, 99, 36);
    expectSortMatches<uint32_t>(300000, Pattern::Random, 98, 20);
}

// The pass shape (digit bits, work-items and keys per work-item; pipeline/sort.cpp picks one per
// device type) changes nothing in the result: the GPU's shape, the earlier CPU one, an odd one and
// wide digits over many one-work-item tiles, run here on the CPU device through
// PHOTONCL_SORT_SHAPE.
TEST(Sort, OtherPassShapesGiveTheSameOrder) {
    for (const char* shape : {"4,256,16", "3,5,7", "8,16,512", "11,1,100", "8,1,16384", "3,5,7,2", "12,1,64,1000"}) {
        SCOPED_TRACE(shape);
        ::setenv("PHOTONCL_SORT_SHAPE", shape, 1);
        uint32_t seed = 500;
        for (size_t n : {size_t(3), size_t(1000), size_t(70001)})
            for (Pattern p : {Pattern::Random, Pattern::FewDistinct}) {
                expectSortMatches<uint32_t>(n, p, seed++);
                expectSortMatches<uint64_t>(n, p, seed++);
            }
        expectSortMatches<uint64_t>(70001, Pattern::Random, seed++, 37);
        ::unsetenv("PHOTONCL_SORT_SHAPE");
    }
}

TEST(Sort, TenMillionRandomKeys32) { expectSortMatches<uint32_t>(10000000, Pattern::Random, 12345); }

TEST(Sort, EmptyAndBadWidth) {
    Device& dev = test::testDevice();
    std::vector<uint32_t> k, v;
    sortPairsOnDevice(dev, k, v);
    EXPECT_TRUE(k.empty());
    cl::Buffer kb = dev.allocate<uint32_t>(4), vb = dev.allocate<uint32_t>(4);
    EXPECT_THROW(sortPairsOnDevice(dev, kb, vb, 4, 16), InternalError);
    EXPECT_THROW(sortPairsOnDevice(dev, kb, vb, 4, 32, 33), InternalError);
}

// The flip: device keys equal the twin's, and sorting by them puts floats in numeric order
// (−0 before +0, both 0.0), infinities and denormals included.
TEST(Sort, FloatKeysPreserveOrder) {
    std::mt19937 rng(3);
    std::vector<float> x = {0.0f,
                            -0.0f,
                            1.0f,
                            -1.0f,
                            std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(),
                            std::numeric_limits<float>::denorm_min(),
                            -std::numeric_limits<float>::denorm_min(),
                            std::numeric_limits<float>::max(),
                            -std::numeric_limits<float>::max(),
                            std::numeric_limits<float>::min()};
    std::normal_distribution<float> normal(0.0f, 100.0f);
    for (int i = 0; i < 100000; ++i) x.push_back(i % 3 ? normal(rng) : std::ldexp(normal(rng), int(rng() % 200) - 100));
    Device& dev = test::testDevice();
    std::vector<uint32_t> keys, values;
    floatSortKeysOnDevice(dev, x, keys, values);
    ASSERT_EQ(keys.size(), x.size());
    for (size_t i = 0; i < x.size(); ++i) {
        ASSERT_EQ(keys[i], referenceFloatKey(x[i])) << "x = " << x[i];
        ASSERT_EQ(values[i], i);
    }
    sortPairsOnDevice(dev, keys, values);
    std::vector<float> sorted(x.size());
    for (size_t i = 0; i < x.size(); ++i) sorted[i] = x[values[i]];
    EXPECT_TRUE(std::is_sorted(sorted.begin(), sorted.end()));
    // ±0 compare equal as floats; the keys put −0 first.
    auto negZero = std::find_if(sorted.begin(), sorted.end(), [](float f) { return f == 0.0f && std::signbit(f); });
    auto posZero = std::find_if(sorted.begin(), sorted.end(), [](float f) { return f == 0.0f && !std::signbit(f); });
    EXPECT_LT(negZero - sorted.begin(), posZero - sorted.begin());
    std::vector<float> want = x;
    std::stable_sort(want.begin(), want.end());
    for (size_t i = 0; i < x.size(); ++i) ASSERT_EQ(sorted[i], want[i]) << i;  // == : ±0 equal
}

}  // namespace
}  // namespace pcl
