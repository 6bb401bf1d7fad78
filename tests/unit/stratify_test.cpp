// kernels/shared/stratify.h: Kensler's correlated multi-jittered samples, as the final gather and
// direct light draw them. Each pattern must be a stratification (one sample per row of v, at most
// one per cell of the m × n grid), and a sample must be uniform over patterns (the estimate stays
// unbiased); the same for a pass's pattern shifted per pixel on the torus, and the kernels' table
// of a pass's cells must be the cells the twins permute.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <set>
#include <vector>

#include "pipeline/pass_strata.h"
#include "shared/rng.h"
#include "shared/stratify.h"
#include "shared/types.h"

namespace {

// Sample s of N of pattern p, jittered within its cell by (jx, jy): Kensler's `cmj`, as the
// cell table and the shift-free sample compose it.
void cmj(uint32_t s, uint32_t N, uint32_t p, float jx, float jy, float* u, float* v) {
    uint32_t a, b;
    stratify_cmj_cell(s, N, p, &a, &b);
    stratify_cell_sample(a, b, stratify_cells(N), N, jx, jy, u, v);
}

// χ² of 2^16 draws of (u, v) (draw(k, &u, &v)) over an 8 × 8 grid of [0,1)², 63 degrees of
// freedom: 99.9 % of uniform draws stay below 103.4.
template <typename Draw>
double chiSquareOverTheGrid(Draw draw) {
    const int draws = 1 << 16, G = 8;
    std::vector<int> hist(G * G, 0);
    for (int k = 0; k < draws; ++k) {
        float u, v;
        draw(uint32_t(k), &u, &v);
        ++hist[int(v * G) * G + int(u * G)];
    }
    const double expect = double(draws) / (G * G);
    double chi2 = 0;
    for (int h : hist) chi2 += (h - expect) * (h - expect) / expect;
    return chi2;
}

TEST(Stratify, PermuteIsABijection) {
    for (uint32_t l : {1u, 2u, 3u, 7u, 16u, 37u, 144u, 1000u}) {
        for (uint32_t p : {0u, 1u, 0xdeadbeefu, 12345u}) {
            std::set<uint32_t> seen;
            for (uint32_t i = 0; i < l; ++i) {
                const uint32_t j = stratify_permute(i, l, p);
                ASSERT_LT(j, l);
                seen.insert(j);
            }
            EXPECT_EQ(seen.size(), l) << "l " << l << " pattern " << p;
        }
    }
}

TEST(Stratify, EveryPatternIsAStratification) {
    for (uint32_t N : {1u, 2u, 5u, 8u, 36u, 72u, 144u, 1000u}) {
        uint32_t m = 1;
        while ((m + 1) * (m + 1) <= N) ++m;
        const uint32_t n = (N + m - 1) / m;
        for (uint32_t p : {7u, 0x9e3779b9u, 424242u}) {
            std::vector<int> row(N, 0), cell(m * n, 0);
            for (uint32_t s = 0; s < N; ++s) {
                uint32_t w[4];
                rng_block(99, p, s, 0, PCL_RNG_STREAM_TEST, w);
                float u, v;
                cmj(s, N, p, rng_u01(w[0]), rng_u01(w[1]), &u, &v);
                ASSERT_GE(u, 0.0f);
                ASSERT_LT(u, 1.0f);
                ASSERT_GE(v, 0.0f);
                ASSERT_LT(v, 1.0f);
                ++row[std::min<uint32_t>(uint32_t(v * float(N)), N - 1)];
                // The cell's column is u's m-stratum, its row v's n-stratum of the same sample.
                const uint32_t cx = std::min<uint32_t>(uint32_t(u * float(m)), m - 1);
                const uint32_t cy = std::min<uint32_t>(uint32_t(v * float(n)), n - 1);
                ++cell[cy * m + cx];
            }
            for (uint32_t r = 0; r < N; ++r) EXPECT_EQ(row[r], 1) << "N " << N << " row " << r;
            for (uint32_t c = 0; c < m * n; ++c) EXPECT_LE(cell[c], 1) << "N " << N << " cell " << c;
        }
    }
}

// One sample index over 2^16 patterns (as the pixels and passes draw them): uniform (χ²).
TEST(Stratify, ASampleIsUniformOverPatterns) {
    for (uint32_t N : {8u, 144u}) {
        for (uint32_t s : {0u, N / 3, N - 1}) {
            const double chi2 = chiSquareOverTheGrid([&](uint32_t k, float* u, float* v) {
                uint32_t w[4];
                rng_block(7, k, 0xFFFFFFFFu, 0, PCL_RNG_STREAM_TEST, w);
                cmj(s, N, w[0], rng_u01(w[1]), rng_u01(w[2]), u, v);
            });
            std::printf("[figure] stratify N %u sample %u: chi2 %.1f over 63 dof\n", N, s, chi2);
            EXPECT_LT(chi2, 103.4) << "N " << N << " sample " << s;
        }
    }
}

// A pass's pattern shifted on the torus (stratify_shifted) is still one sample per row of v and
// per fine column of u, counted from the shift.
TEST(Stratify, AShiftedPatternIsAStratificationOnTheTorus) {
    for (uint32_t N : {1u, 8u, 36u, 72u, 144u, 1000u}) {
        const uint32_t cells = stratify_cells(N);
        for (uint32_t p : {7u, 0x9e3779b9u}) {
            for (const float su : {0.0f, 0.37f, 0.999f}) {
                const float sv = 1.0f - su * 0.5f;
                std::vector<int> row(N, 0), column(cells, 0);
                for (uint32_t s = 0; s < N; ++s) {
                    uint32_t a, b;
                    stratify_cmj_cell(s, N, p, &a, &b);
                    ASSERT_LT(a, cells);
                    ASSERT_LT(b, N);
                    float u, v;
                    stratify_shifted(a, b, cells, N, 0.5f, 0.5f, su, sv < 1.0f ? sv : 0.0f, &u, &v);
                    ASSERT_GE(u, 0.0f);
                    ASSERT_LT(u, 1.0f);
                    ASSERT_GE(v, 0.0f);
                    ASSERT_LT(v, 1.0f);
                    // Jittered to the cell's middle, so the unshifted point lies half a cell from
                    // every edge: its row and column survive the float rounding.
                    float u0 = u - su, v0 = v - (sv < 1.0f ? sv : 0.0f);
                    u0 = u0 < 0.0f ? u0 + 1.0f : u0;
                    v0 = v0 < 0.0f ? v0 + 1.0f : v0;
                    ++row[std::min<uint32_t>(uint32_t(v0 * float(N)), N - 1)];
                    ++column[std::min<uint32_t>(uint32_t(u0 * float(cells)), cells - 1)];
                }
                for (uint32_t r = 0; r < N; ++r) EXPECT_EQ(row[r], 1) << "N " << N << " row " << r;
                for (uint32_t c = 0; c < cells; ++c) EXPECT_LE(column[c], 1) << "N " << N << " column " << c;
            }
        }
    }
}

// One sample of one fixed pattern over 2^16 shifts (the pixels of a pass): uniform (χ², 63 dof).
TEST(Stratify, AShiftedSampleIsUniformOverShifts) {
    for (uint32_t N : {8u, 72u}) {
        for (uint32_t s : {0u, N / 3, N - 1}) {
            uint32_t a, b;
            stratify_cmj_cell(s, N, 0x1234567u, &a, &b);
            const double chi2 = chiSquareOverTheGrid([&](uint32_t k, float* u, float* v) {
                uint32_t w[4];
                rng_block(11, k, 0xFFFFFFFFu, 0, PCL_RNG_STREAM_TEST, w);
                stratify_shifted(a, b, stratify_cells(N), N, rng_u01(w[0]), rng_u01(w[1]), rng_u01(w[2]), rng_u01(w[3]),
                                 u, v);
            });
            std::printf("[figure] stratify shifted N %u sample %u: chi2 %.1f over 63 dof\n", N, s, chi2);
            EXPECT_LT(chi2, 103.4) << "N " << N << " sample " << s;
        }
    }
}

// The table the kernels read (pipeline/pass_strata) holds the cells the twins permute.
TEST(Stratify, PassStrataTableHoldsEachPatternsCells) {
    const uint64_t seed = 0x123456789abcull;
    for (uint32_t count : {0u, 1u, 72u, 288u}) {
        const std::vector<uint32_t> t = pcl::passStrata(seed, PCL_RNG_STREAM_LIGHT, PCL_LIGHT_PATTERN_BOUNCE, 2, count);
        ASSERT_EQ(t.size(), std::max<size_t>(4 * count, 2));
        uint32_t words[4];
        rng_block(seed, PCL_PASS_PATTERN_PATH, PCL_LIGHT_PATTERN_BOUNCE, 0, PCL_RNG_STREAM_LIGHT, words);
        for (uint32_t w = 0; w < 2; ++w)
            for (uint32_t s = 0; s < count; ++s) {
                uint32_t a, b;
                stratify_cmj_cell(s, count, words[w], &a, &b);
                EXPECT_EQ(t[2 * (w * count + s)], a);
                EXPECT_EQ(t[2 * (w * count + s) + 1], b);
            }
    }
}

}  // namespace
