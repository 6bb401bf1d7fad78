// Philox4x32-10 on the host: the published known-answer vectors, the [0,1) mapping, the
// counter layout, and a chi-square test of uniformity.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "shared/rng.h"

namespace {

struct Kat {
    std::array<pcl_u32, 4> ctr;
    std::array<pcl_u32, 2> key;
    std::array<pcl_u32, 4> expected;
};

// Random123 kat_vectors, philox4x32 with 10 rounds.
const Kat kKats[] = {
    {{0, 0, 0, 0}, {0, 0}, {0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8}},
    {{0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff},
     {0xffffffff, 0xffffffff},
     {0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd}},
    {{0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344},
     {0xa4093822, 0x299f31d0},
     {0xd16cfe09, 0x94fdcceb, 0x5001e420, 0x24126ea1}},
};

TEST(Rng, PhiloxKnownAnswers) {
    for (const Kat& k : kKats) {
        pcl_u32 out[4];
        rng_philox4x32_10(k.ctr.data(), k.key.data(), out);
        for (int i = 0; i < 4; ++i) EXPECT_EQ(out[i], k.expected[i]) << "word " << i;
    }
}

TEST(Rng, U01IsInHalfOpenUnitInterval) {
    EXPECT_EQ(rng_u01(0u), 0.0f);
    EXPECT_EQ(rng_u01(0xFFu), 0.0f);       // the low 8 bits are dropped
    EXPECT_EQ(rng_u01(0x100u), 0x1p-24f);  // one step is 2^-24
    EXPECT_EQ(rng_u01(0xFFFFFFFFu), 1.0f - 0x1p-24f);
    EXPECT_LT(rng_u01(0xFFFFFFFFu), 1.0f);
}

// rng_next walks the dimensions of rng_uniform_at, four per Philox call.
TEST(Rng, StreamMatchesIndexedDimensions) {
    const pcl_u64 seed = 0x0123456789ABCDEFull;
    PclRng r = rng_start(seed, 17, 3, PCL_RNG_STREAM_CAMERA);
    for (pcl_u32 d = 0; d < 37; ++d)
        EXPECT_EQ(rng_next(&r), rng_uniform_at(seed, 17, 3, PCL_RNG_STREAM_CAMERA, d)) << "dim " << d;
}

// Every counter and key word changes the output: the layout really is (seed, path, bounce, dim).
TEST(Rng, EveryIndexMatters) {
    const pcl_u64 seed = 42;
    const float base = rng_uniform_at(seed, 5, 2, 0, 1);
    EXPECT_NE(base, rng_uniform_at(seed + (1ull << 32), 5, 2, 0, 1));  // high seed word
    EXPECT_NE(base, rng_uniform_at(seed + 1, 5, 2, 0, 1));
    EXPECT_NE(base, rng_uniform_at(seed, 6, 2, 0, 1));
    EXPECT_NE(base, rng_uniform_at(seed, 5, 3, 0, 1));
    EXPECT_NE(base, rng_uniform_at(seed, 5, 2, 1, 1));
    EXPECT_NE(base, rng_uniform_at(seed, 5, 2, 0, 5));  // next block, same lane
}

// Pearson's chi-square over 100 equal bins, 10^6 samples (paths 0..249999, dimensions 0..3).
// df = 99; the critical value for alpha = 0.001 is 148.2 (Wilson–Hilferty). The samples are
// fixed by the seed, so the outcome is deterministic; a generator or mapping bug (a stuck bit,
// a wrong shift) pushes the statistic into the thousands.
TEST(Rng, UniformChiSquare1D) {
    const int bins = 100;
    const int paths = 250000;
    std::vector<double> count(bins, 0.0);
    for (int p = 0; p < paths; ++p) {
        PclRng r = rng_start(7, pcl_u32(p), 0, PCL_RNG_STREAM_TEST);
        for (int d = 0; d < 4; ++d) {
            float u = rng_next(&r);
            ASSERT_GE(u, 0.0f);
            ASSERT_LT(u, 1.0f);
            count[int(u * bins)] += 1;
        }
    }
    const double expected = 4.0 * paths / bins;
    double chi2 = 0;
    for (double c : count) chi2 += (c - expected) * (c - expected) / expected;
    EXPECT_LT(chi2, 148.2);
}

// Pairs of consecutive dimensions over a 16 x 16 grid, 10^6 pairs, so correlation between the
// words of one block, or between neighbouring paths, would show. df = 255; the critical value
// for alpha = 0.001 is 330.5 (Wilson–Hilferty).
TEST(Rng, UniformChiSquare2D) {
    const int side = 16;
    const int paths = 500000;
    std::vector<double> count(side * side, 0.0);
    for (int p = 0; p < paths; ++p) {
        PclRng r = rng_start(11, pcl_u32(p), 1, PCL_RNG_STREAM_TEST);
        for (int pair = 0; pair < 2; ++pair) {
            int x = int(rng_next(&r) * side), y = int(rng_next(&r) * side);
            count[y * side + x] += 1;
        }
    }
    const double expected = 2.0 * paths / (side * side);
    double chi2 = 0;
    for (double c : count) chi2 += (c - expected) * (c - expected) / expected;
    EXPECT_LT(chi2, 330.5);
}

}  // namespace
