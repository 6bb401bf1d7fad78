// The per-pixel Z-test (image/metrics.h): unbiased noise passes at the rate Student's t
// predicts, a bias of a few standard errors fails, constant and non-finite pixels are handled.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "core/error.h"
#include "image/metrics.h"

using namespace pcl;

namespace {

// K renders: reference + bias + Gaussian noise of standard deviation sigma per channel.
std::vector<Image> noisyRuns(const Image& reference, int k, double sigma, double bias, uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, sigma);
    std::vector<Image> runs;
    for (int r = 0; r < k; ++r) {
        Image img = reference;
        for (float& v : img.rgb) v = static_cast<float>(v + bias + noise(rng));
        runs.push_back(img);
    }
    return runs;
}

Image flat(int w, int h, float v) {
    Image img(w, h);
    for (float& x : img.rgb) x = v;
    return img;
}

}  // namespace

TEST(PerPixelZTest, UnbiasedNoisePassesAtTheStudentTRate) {
    Image reference = flat(100, 100, 1.0f);
    ZTestResult z = perPixelZTest(noisyRuns(reference, 16, 0.1, 0.0, 1), reference, 4.0);
    std::printf("[figure] Z-test on unbiased Gaussian noise, K = 16, 10000 pixels: %s\n", formatZTest(z).c_str());
    // t with 15 degrees of freedom: P(|t| >= 4) = 0.0012, so about 12 of 10000 fail; 0.995 leaves
    // a margin of four binomial standard deviations.
    EXPECT_GT(z.passFraction(), 0.995);
    EXPECT_EQ(z.pixels, 10000u);
    EXPECT_EQ(z.nonFinite, 0u);
    // E|t_ν| = 2 sqrt(ν/π) Γ((ν+1)/2) / ((ν−1) Γ(ν/2)) = 0.8408 for ν = 15; within 3 %.
    EXPECT_NEAR(z.meanAbsZ, 0.841, 0.025);
}

TEST(PerPixelZTest, BiasOfSeveralStandardErrorsFails) {
    Image reference = flat(50, 50, 1.0f);
    // The channel sum's standard error of the mean is 0.1·sqrt(3)/4 = 0.0433; a bias of 0.1 per
    // channel (0.3 on the sum) is ~7 standard errors.
    ZTestResult z = perPixelZTest(noisyRuns(reference, 16, 0.1, 0.1, 2), reference, 4.0);
    std::printf("[figure] Z-test, bias 7 standard errors: %s\n", formatZTest(z).c_str());
    EXPECT_LT(z.passFraction(), 0.2);
}

TEST(PerPixelZTest, ReferenceVarianceWidensTheTest) {
    Image reference = flat(50, 50, 1.0f);
    std::vector<Image> runs = noisyRuns(reference, 16, 0.1, 0.1, 3);
    Image variance = flat(50, 50, 0.0f);
    for (size_t i = 0; i < variance.pixelCount(); ++i) variance.rgb[3 * i] = 0.3f * 0.3f;  // the bias is 1 σ_ref
    ZTestResult z = perPixelZTest(runs, reference, 4.0, &variance);
    EXPECT_GT(z.passFraction(), 0.99);
}

TEST(PerPixelZTest, ConstantPixelsAndNonFiniteValues) {
    Image reference = flat(4, 4, 2.0f);
    std::vector<Image> runs(16, reference);
    ZTestResult same = perPixelZTest(runs, reference);
    EXPECT_EQ(same.passed, 16u);  // equal constants pass without dividing by zero
    EXPECT_TRUE(same.failed.empty());
    std::vector<Image> halfRounded(16, flat(4, 4, 2.0f * (1.0f + 4.8e-4f)));  // within half-float rounding
    EXPECT_EQ(perPixelZTest(halfRounded, reference).passed, 16u);
    runs[0].rgb[0] = 2.5f;  // one render differs: ordinary test
    std::vector<Image> constantOff(16, flat(4, 4, 2.1f));
    ZTestResult off = perPixelZTest(constantOff, reference);
    EXPECT_EQ(off.passed, 0u);  // zero variance but a different value fails
    EXPECT_EQ(off.failed.size(), 16u);
    EXPECT_TRUE(std::isinf(off.maxAbsZ));
    runs[3].rgb[5] = std::numeric_limits<float>::quiet_NaN();
    ZTestResult nan = perPixelZTest(runs, reference);
    EXPECT_EQ(nan.nonFinite, 1u);
    EXPECT_EQ(nan.passed, 15u);
    size_t bad = 0;
    EXPECT_FALSE(allFinite(runs[3], &bad));
    EXPECT_EQ(bad, 1u);
    EXPECT_TRUE(allFinite(reference));
}

TEST(PerPixelZTest, RejectsTooFewRunsAndSizeMismatch) {
    Image reference = flat(4, 4, 1.0f);
    EXPECT_THROW(perPixelZTest({reference}, reference), InputError);
    EXPECT_THROW(perPixelZTest({reference, flat(4, 5, 1.0f)}, reference), InputError);
}
