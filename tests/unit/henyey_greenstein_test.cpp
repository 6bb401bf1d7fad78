// The Henyey–Greenstein phase function of reference/medium.h against its closed forms: the
// density integrates to 1 and its mean cosine is g; sampled directions follow the density (χ²
// over the scattering-angle cosine against the analytic CDF, independent of the inversion the
// sampler uses) and have mean cosine g.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "core/math.h"
#include "reference/medium.h"

using namespace pcl;

namespace {

constexpr float kGs[] = {-0.9f, -0.3f, 0.0f, 0.5f, 0.9f};

// P(μ' ≤ μ) of the HG density over the cosine: (1 − g²)/(2g) (1/√(1 + g² − 2gμ) − 1/(1 + g)).
double hgCdf(double mu, double g) {
    if (g == 0.0) return 0.5 * (1.0 + mu);
    return (1.0 - g * g) / (2.0 * g) * (1.0 / std::sqrt(1.0 + g * g - 2.0 * g * mu) - 1.0 / (1.0 + g));
}

// Simpson's rule of f over [-1, 1] with n (even) intervals.
template <class F>
double simpson(F f, int n) {
    const double h = 2.0 / n;
    double s = f(-1.0) + f(1.0);
    for (int i = 1; i < n; ++i) s += f(-1.0 + i * h) * (i % 2 ? 4.0 : 2.0);
    return s * h / 3.0;
}

}  // namespace

// ∫ p dω = 2π ∫ p(μ) dμ = 1 and 2π ∫ μ p(μ) dμ = g, by quadrature of the evaluated density.
TEST(HenyeyGreenstein, DensityIntegratesToOneWithMeanCosineG) {
    for (float g : kGs) {
        const double norm = simpson([&](double mu) { return 2.0 * kPiD * henyeyGreenstein(float(mu), g); }, 200000);
        const double mean =
            simpson([&](double mu) { return 2.0 * kPiD * mu * henyeyGreenstein(float(mu), g); }, 200000);
        std::printf("g %+.1f: integral %.7f, mean cosine %+.7f\n", g, norm, mean);
        EXPECT_NEAR(norm, 1.0, 1e-5) << "g " << g;  // Simpson's error at g = ±0.9 is ~1e-9
        EXPECT_NEAR(mean, g, 1e-5) << "g " << g;
    }
}

// Sampled directions: χ² of the scattering-angle cosines in 40 equal bins of μ against the CDF;
// the mean cosine within 0.01 of g (σ ≤ 1/√200000 = 0.0022); wi is a unit vector.
TEST(HenyeyGreenstein, SamplesFollowTheDensity) {
    const int n = 200000, bins = 40;
    const Vec3 wo = normalize(Vec3(0.3f, -0.5f, 0.8f));  // any incoming direction; forward is −wo
    for (float g : kGs) {
        std::mt19937 rng(17);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        std::vector<int> counts(bins, 0);
        double sumMu = 0.0, worstLength = 0.0;
        for (int i = 0; i < n; ++i) {
            const Vec3 wi = sampleHenyeyGreenstein(wo, g, u(rng), u(rng));
            worstLength = std::max(worstLength, std::abs(double(length(wi)) - 1.0));
            const double mu = std::clamp(double(dot(-wo, wi)), -1.0, 1.0);
            sumMu += mu;
            counts[std::min(bins - 1, int((mu + 1.0) * 0.5 * bins))]++;
        }
        double chi2 = 0.0;
        for (int b = 0; b < bins; ++b) {
            const double expected = n * (hgCdf(-1.0 + 2.0 * (b + 1) / bins, g) - hgCdf(-1.0 + 2.0 * b / bins, g));
            chi2 += (counts[b] - expected) * (counts[b] - expected) / expected;
        }
        const double mean = sumMu / n;
        std::printf("g %+.1f: chi2 %.1f (39 dof), mean cosine %+.4f\n", g, chi2, mean);
        // 39 degrees of freedom: P(χ² > 80) ≈ 1e-4.
        EXPECT_LT(chi2, 80.0) << "g " << g;
        EXPECT_NEAR(mean, g, 0.01) << "g " << g;
        EXPECT_LT(worstLength, 1e-5);
    }
}

// The inverted CDF in closed form hits the ends of [−1, 1] and the median of the CDF.
TEST(HenyeyGreenstein, InverseCdfEndpoints) {
    for (float g : kGs) {
        EXPECT_NEAR(sampleHenyeyGreensteinCosine(g, 0.0f), -1.0f, 1e-5f) << g;
        EXPECT_NEAR(sampleHenyeyGreensteinCosine(g, 1.0f), 1.0f, 1e-5f) << g;
        EXPECT_NEAR(hgCdf(sampleHenyeyGreensteinCosine(g, 0.5f), g), 0.5, 1e-5) << g;
    }
}
