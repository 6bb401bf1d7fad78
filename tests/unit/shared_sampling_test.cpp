// kernels/shared/sampling.h compiled for the host: the warps and encodings the photon kernels
// use, checked against their definitions (kernels/README.md) without a device.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "shared/sampling.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

double len(PclV3 v) { return std::sqrt(double(v.x) * v.x + double(v.y) * v.y + double(v.z) * v.z); }

PclV3 randomUnit(std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    return sampling_uniform_sphere(u(rng), u(rng));
}

float floatFromBits(uint32_t b) {
    float f;
    std::memcpy(&f, &b, sizeof f);
    return f;
}

TEST(SharedSampling, BasisIsOrthonormalEverywhereIncludingTheSouthPole) {
    std::mt19937 rng(1);
    for (int i = 0; i < 10000; ++i) {
        PclV3 n = i == 0 ? sampling_v3(0, 0, -1) : i == 1 ? sampling_v3(0, 0, 1) : randomUnit(rng);
        PclV3 t, b;
        sampling_basis(n, &t, &b);
        ASSERT_NEAR(len(t), 1.0, 1e-5);
        ASSERT_NEAR(len(b), 1.0, 1e-5);
        ASSERT_NEAR(sampling_dot(t, b), 0.0, 1e-5);
        ASSERT_NEAR(sampling_dot(t, n), 0.0, 1e-5);
        ASSERT_NEAR(sampling_dot(b, n), 0.0, 1e-5);
        // Right-handed: t × b = n.
        ASSERT_NEAR(t.y * b.z - t.z * b.y, n.x, 1e-5);
    }
}

TEST(SharedSampling, ConcentricDiskIsAreaPreservingAndCosineLobeIsAHemisphere) {
    const int n = 256;
    double r2 = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            float x, y;
            sampling_concentric_disk((i + 0.5f) / n, (j + 0.5f) / n, &x, &y);
            ASSERT_LE(x * x + y * y, 1.0f + 1e-6f);
            r2 += x * x + y * y;
        }
    EXPECT_NEAR(r2 / (n * n), 0.5, 1e-4);  // uniform on the disk: E[r²] = 1/2
    PclV3 axis = sampling_v3(0.6f, 0.0f, 0.8f);
    double c = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            PclV3 d = sampling_cosine_hemisphere(axis, (i + 0.5f) / n, (j + 0.5f) / n);
            ASSERT_NEAR(len(d), 1.0, 1e-5);
            ASSERT_GE(sampling_dot(d, axis), -1e-6f);
            c += sampling_dot(d, axis);
        }
    EXPECT_NEAR(c / (n * n), 2.0 / 3.0, 1e-3);  // E[cosθ] under cosθ/π
}

// The concentric map's sin and cos (Taylor polynomials on [-π/4, π/4], no argument reduction)
// within 2 ulps of 1 of the double-precision functions at 2^20 + 1 angles, the ends included;
// and the map itself, at 512² square points, within 3e-7 of the polar formula in doubles.
TEST(SharedSampling, QuarterRangeSinCosAndTheConcentricMapMatchTheLibrary) {
    const int n = 1 << 20;
    double worst = 0;
    for (int i = 0; i <= n; ++i) {
        const float t = float(-kPi / 4 + (kPi / 2) * i / n);
        float s, c;
        sampling_sincos_quarter(t, &s, &c);
        worst = std::max({worst, std::fabs(s - std::sin(double(t))), std::fabs(c - std::cos(double(t)))});
    }
    EXPECT_LE(worst, 2.0 * 0x1p-24) << worst;
    const int m = 512;
    double mapWorst = 0;
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) {
            const float s1 = (i + 0.5f) / m, s2 = (j + 0.5f) / m;
            float x, y;
            sampling_concentric_disk(s1, s2, &x, &y);
            const double a = 2.0 * s1 - 1.0, b = 2.0 * s2 - 1.0;
            const bool wide = std::fabs(a) > std::fabs(b);
            const double r = wide ? a : b, phi = wide ? kPi / 4 * (b / a) : kPi / 2 - kPi / 4 * (a / b);
            mapWorst = std::max({mapWorst, std::fabs(x - r * std::cos(phi)), std::fabs(y - r * std::sin(phi))});
        }
    EXPECT_LE(mapWorst, 3e-7) << mapWorst;
}

TEST(SharedSampling, SpotCosThetaInvertsTheFalloffCdf) {
    const float cosInner = 0.9f, cosOuter = 0.3f;
    const double wIn = 1.0 - cosInner, wFall = (cosInner - cosOuter) / 2.0, pIn = wIn / (wIn + wFall);
    for (int i = 0; i < 1000; ++i) {
        float s1 = (i + 0.5f) / 1000.0f;
        double c = sampling_spot_cos_theta(s1, cosInner, cosOuter);
        ASSERT_GE(c, cosOuter - 1e-6);
        ASSERT_LE(c, 1.0 + 1e-6);
        // The CDF from the axis outwards in the core, from the outer edge inwards in the falloff.
        double back;
        if (c >= cosInner && s1 < pIn) {
            back = (1.0 - c) / (wIn + wFall);
        } else {
            double t = (c - cosOuter) / (cosInner - cosOuter);
            back = pIn + (1.0 - pIn) * (2 * t * t * t - t * t * t * t);
        }
        ASSERT_NEAR(back, s1, 2e-6) << "s1 " << s1;
    }
}

TEST(SharedSampling, FresnelAndRefractionFollowSnell) {
    const float ior = 1.5f;
    EXPECT_NEAR(sampling_fresnel_dielectric(1.0f, 1.0f / ior), 0.04, 1e-6);  // ((1-n)/(1+n))²
    EXPECT_NEAR(sampling_fresnel_dielectric(1.0f, ior), 0.04, 1e-6);
    EXPECT_EQ(sampling_fresnel_dielectric(0.5f, ior), 1.0f);                 // beyond the critical angle
    EXPECT_NEAR(sampling_fresnel_dielectric(1e-4f, 1.0f / ior), 1.0, 1e-3);  // grazing
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u(0.05f, 0.999f);
    PclV3 n = sampling_v3(0, 0, 1);
    for (int i = 0; i < 1000; ++i) {
        float cosI = u(rng), phi = 6.2831853f * u(rng);
        float sinI = std::sqrt(1 - cosI * cosI);
        PclV3 d = sampling_v3(sinI * std::cos(phi), sinI * std::sin(phi), -cosI);  // arriving from above
        float eta = 1.0f / ior;
        PclV3 t = sampling_refract(d, n, cosI, eta);
        ASSERT_NEAR(len(t), 1.0, 1e-5);
        ASSERT_LT(t.z, 0.0f);
        double sinT = std::sqrt(1.0 - double(t.z) * t.z);
        ASSERT_NEAR(sinT, eta * sinI, 1e-5);
        // Reciprocity: the reflectance is the same going back out along the refracted ray.
        ASSERT_NEAR(sampling_fresnel_dielectric(-t.z, ior), sampling_fresnel_dielectric(cosI, eta), 1e-4);
        PclV3 r = sampling_reflect(d, n);
        ASSERT_NEAR(r.z, -d.z, 1e-6);
        ASSERT_NEAR(r.x, d.x, 1e-6);
    }
}

TEST(SharedSampling, PhongLobeStaysAroundItsAxis) {
    PclV3 r = sampling_v3(0.0f, 0.6f, 0.8f);
    const float e = 20.0f;
    const int n = 200;
    double c = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            PclV3 d = sampling_phong_lobe(r, e, (i + 0.5f) / n, (j + 0.5f) / n);
            ASSERT_NEAR(len(d), 1.0, 1e-5);
            c += sampling_dot(d, r);
        }
    EXPECT_NEAR(c / (n * n), (e + 1) / (e + 2), 1e-3);  // E[cosα] under (n+1)/(2π) cosⁿα
}

TEST(SharedSampling, RgbeKeepsEightBitsOfTheLargestChannel) {
    EXPECT_EQ(photon_rgbe_encode(0, 0, 0), 0u);
    EXPECT_EQ(photon_rgbe_encode(1e-33f, 0, 0), 0u);
    float r, g, b;
    photon_rgbe_decode(0u, &r, &g, &b);
    EXPECT_EQ(r + g + b, 0.0f);
    // 1.0: frexp gives (0.5, 1), bytes 128, exponent 129; decode 128 · 2^-7 = 1.
    uint32_t one = photon_rgbe_encode(1.0f, 0.5f, 0.25f);
    EXPECT_EQ(one, 128u | (64u << 8) | (32u << 16) | (129u << 24));
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), ex(-30.0f, 30.0f);
    for (int i = 0; i < 100000; ++i) {
        float scale = std::pow(2.0f, ex(rng));
        float c[3] = {u(rng) * scale, u(rng) * scale, u(rng) * scale};
        float m = std::max(c[0], std::max(c[1], c[2]));
        photon_rgbe_decode(photon_rgbe_encode(c[0], c[1], c[2]), &r, &g, &b);
        ASSERT_NEAR(r, c[0], m / 256.0f);
        ASSERT_NEAR(g, c[1], m / 256.0f);
        ASSERT_NEAR(b, c[2], m / 256.0f);
    }
}

TEST(SharedSampling, FloorToByteIsTheClampedFloorForEveryFloat) {
    // Against min(255, max(0, ⌊x⌋)) (NaN to 0), the channel byte as the README defines it:
    // every 997th float of either sign, and every float in [0, 257] beside an integer.
    auto want = [](float x) {
        float f = std::floor(x);
        return f > 255.0f ? 255u : (f > 0.0f ? uint32_t(f) : 0u);
    };
    for (uint64_t b = 0; b <= 0xFFFFFFFFull; b += 997) {
        float x = floatFromBits(uint32_t(b));
        ASSERT_EQ(photon_floor_to_byte(x), want(x)) << x;
    }
    for (int k = 0; k <= 257; ++k)
        for (float toward : {-1.0f, 300.0f}) {
            float x = float(k);
            for (int s = 0; s < 64; ++s, x = std::nextafter(x, toward))
                ASSERT_EQ(photon_floor_to_byte(x), want(x)) << x;
        }
}

TEST(SharedSampling, DirectionBytesRoundTripWithinABin) {
    std::mt19937 rng(4);
    for (int i = 0; i < 100000; ++i) {
        PclV3 w = randomUnit(rng);
        uint32_t packed = photon_dir_encode(w.x, w.y, w.z);
        ASSERT_EQ(packed >> 16, 0u);
        PclV3 back = photon_dir_decode(packed);
        // θ bins are π/256 wide, φ bins π/128: the bin centre is within about 1° of w.
        ASSERT_GT(sampling_dot(w, back), std::cos(1.2 * kPi / 180.0)) << w.x << " " << w.y << " " << w.z;
    }
    // A z a rounding error past 1 still encodes θ = 0, not NaN.
    EXPECT_EQ(photon_dir_encode(0.0f, 0.0f, 1.0000001f) & 255u, 0u);
    EXPECT_EQ(photon_dir_encode(0.0f, 0.0f, -1.0f) & 255u, 255u);
    // φ wraps two's-complement: atan2 just below 0 lands in byte 255.
    EXPECT_EQ((photon_dir_encode(1.0f, -1e-3f, 0.0f) >> 8) & 255u, 255u);
    EXPECT_EQ((photon_dir_encode(1.0f, 1e-3f, 0.0f) >> 8) & 255u, 0u);
}

// photon_dir_encode's bytes as the README defines them, straight from the library (the
// encoding before its fast path, and the twin's).
uint32_t thetaByteByLibrary(float wz) {
    float z = wz > 1.0f ? 1.0f : (wz < -1.0f ? -1.0f : wz);
    float th = std::floor(std::acos(z) * 256.0f / PCL_PI_F);
    return th > 255.0f ? 255u : (th > 0.0f ? uint32_t(th) : 0u);
}
uint32_t phiByteByLibrary(float wx, float wy) {
    return uint32_t(int32_t(std::floor(std::atan2(wy, wx) * 128.0f / PCL_PI_F))) & 255u;
}

TEST(SharedSampling, ApproximateAcosAndAtan2StayWellInsideTheByteMargin) {
    // The fast path is safe when its error, in byte units, is far below PCL_DIR_BYTE_MARGIN.
    double worstTheta = 0, worstPhi = 0;
    for (int i = 0; i <= 200000; ++i) {
        float z = -1.0f + 2.0f * float(i) / 200000.0f;
        worstTheta = std::max(worstTheta, std::abs(double(sampling_acos_approx(z)) - std::acos(double(z))));
    }
    std::mt19937 rng(11);
    for (int i = 0; i < 200000; ++i) {
        PclV3 w = randomUnit(rng);
        worstPhi = std::max(worstPhi,
                            std::abs(double(sampling_atan2_approx(w.y, w.x)) - std::atan2(double(w.y), double(w.x))));
    }
    EXPECT_LT(worstTheta * 256.0 / kPi, PCL_DIR_BYTE_MARGIN / 10.0) << worstTheta;
    EXPECT_LT(worstPhi * 128.0 / kPi, PCL_DIR_BYTE_MARGIN / 10.0) << worstPhi;
}

TEST(SharedSampling, DirectionBytesAreTheLibrarysAtEveryThetaAndBesideEveryEdge) {
    // θ depends on w_z alone: every 1021st float in [-1, 1] (all 2.1e9 were checked
    // once, with no difference), and every float within 256 ulps of each bin edge.
    auto checkZ = [](float z) { ASSERT_EQ(photon_dir_encode(0.6f, 0.8f, z) & 255u, thetaByteByLibrary(z)) << z; };
    for (uint32_t b = 0; b <= 0x3F800000u; b += 1021) {
        checkZ(floatFromBits(b));
        checkZ(-floatFromBits(b));
    }
    for (int k = 0; k <= 256; ++k) {
        float edge = float(std::cos(k * kPi / 256.0));
        for (float toward : {-2.0f, 2.0f}) {
            float z = edge;
            for (int s = 0; s <= 256; ++s, z = std::nextafter(z, toward)) checkZ(z);
        }
    }
    // φ: directions beside every bin edge (angles kπ/128 nudged by 0..64 ulps in x and y, at
    // several lengths and elevations) and random unit vectors.
    int checked = 0;
    for (int k = -128; k <= 128; ++k)
        for (float r : {1.0f, 0.3f, 1e-3f})
            for (int d = -64; d <= 64; d += 4) {
                float x = float(r * std::cos(k * kPi / 128.0)), y = float(r * std::sin(k * kPi / 128.0));
                for (int s = 0; s < std::abs(d); ++s) {
                    x = std::nextafter(x, d < 0 ? -2.0f : 2.0f);
                    y = std::nextafter(y, d < 0 ? 2.0f : -2.0f);
                }
                for (float yy : {y, d == 0 && y == 0.0f ? -0.0f : y}) {
                    ASSERT_EQ((photon_dir_encode(x, yy, 0.1f) >> 8) & 255u, phiByteByLibrary(x, yy))
                        << k << " " << x << " " << yy;
                    ++checked;
                }
            }
    std::mt19937 rng(12);
    for (int i = 0; i < 1000000; ++i) {
        PclV3 w = randomUnit(rng);
        ASSERT_EQ(photon_dir_encode(w.x, w.y, w.z), thetaByteByLibrary(w.z) | (phiByteByLibrary(w.x, w.y) << 8));
    }
    EXPECT_GT(checked, 20000);
    // Signed zeros and the ±π edge: atan2(±0, -1) = ±π, bytes 128 both ways.
    EXPECT_EQ((photon_dir_encode(-1.0f, 0.0f, 0.0f) >> 8) & 255u, 128u);
    EXPECT_EQ((photon_dir_encode(-1.0f, -0.0f, 0.0f) >> 8) & 255u, 128u);
    EXPECT_EQ((photon_dir_encode(1.0f, -0.0f, 0.0f) >> 8) & 255u, 0u);
}

}  // namespace
