// Warps from uniform numbers in [0,1)^2 to directions and points, with their densities, and
// the MIS weight. References: pbrt-v4 ch. A.5 (sampling functions), Shirley & Chiu 1997
// (concentric disk), Veach 1997 §9.2 (power heuristic).
#pragma once
#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "core/vec3.h"
#include "shared/sampling.h"

namespace pcl {

constexpr float kInvPi = 1.0f / kPi;

// smoothstep(e0, e1, x): 0 below e0, 1 above e1, t²(3 − 2t) between (a step when e1 ≤ e0).
inline float smoothstep(float e0, float e1, float x) {
    if (e1 <= e0) return x >= e1 ? 1.0f : 0.0f;
    const float t = std::min(1.0f, std::max(0.0f, (x - e0) / (e1 - e0)));
    return t * t * (3.0f - 2.0f * t);
}

// Shirley–Chiu concentric map of the square onto the unit disk (area-preserving, low distortion).
inline void sampleConcentricDisk(float u1, float u2, float& x, float& y) {
    // The kernels' map (shared/sampling.h), so the twins and the reference draw the same floats.
    sampling_concentric_disk(u1, u2, &x, &y);
}

// Direction from (sinθ, cosθ, φ) in the frame (t, b, n).
inline Vec3 fromLocal(Vec3 t, Vec3 b, Vec3 n, float sinTheta, float cosTheta, float phi) {
    return t * (sinTheta * std::cos(phi)) + b * (sinTheta * std::sin(phi)) + n * cosTheta;
}

// Cosine-weighted hemisphere around n (Malley's method): pdf = cosθ / π.
inline Vec3 sampleCosineHemisphere(Vec3 n, float u1, float u2) {
    float x, y;
    sampleConcentricDisk(u1, u2, x, y);
    float z = std::sqrt(std::max(0.0f, 1.0f - x * x - y * y));
    Vec3 t, b;
    makeBasis(n, t, b);
    return t * x + b * y + n * z;
}

// cos^e lobe around axis a: pdf = (e + 1) / (2π) cos^e α (the sampling density of the
// normalised Phong lobe; Lafortune & Willems 1994).
inline Vec3 samplePhongLobe(Vec3 a, float exponent, float u1, float u2) {
    float cosA = std::pow(u1, 1.0f / (exponent + 1.0f));
    float sinA = std::sqrt(std::max(0.0f, 1.0f - cosA * cosA));
    Vec3 t, b;
    makeBasis(a, t, b);
    return fromLocal(t, b, a, sinA, cosA, 2.0f * kPi * u2);
}
inline float phongLobePdf(float cosAlpha, float exponent) {
    return cosAlpha > 0.0f ? (exponent + 1.0f) * (0.5f * kInvPi) * std::pow(cosAlpha, exponent) : 0.0f;
}

// Uniform on the unit sphere: pdf = 1 / (4π).
inline Vec3 sampleUniformSphere(float u1, float u2) {
    float z = 1.0f - 2.0f * u1;
    float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    float phi = 2.0f * kPi * u2;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// Uniform on a triangle (pbrt-v3 UniformSampleTriangle): barycentrics (b0, b1) of p0 and p1.
inline void sampleUniformTriangle(float u1, float u2, float& b0, float& b1) {
    float su0 = std::sqrt(u1);
    b0 = 1.0f - su0;
    b1 = u2 * su0;
}

// Veach's power heuristic with β = 2 for one sample from each of two strategies.
inline float powerHeuristic(float pdfA, float pdfB) {
    float a = pdfA * pdfA, b = pdfB * pdfB;
    return a + b > 0.0f ? a / (a + b) : 0.0f;
}

inline Vec3 reflect(Vec3 wo, Vec3 n) { return 2.0f * dot(wo, n) * n - wo; }  // wo, result point away

}  // namespace pcl
