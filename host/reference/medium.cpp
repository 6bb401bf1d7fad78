#include "reference/medium.h"

#include <algorithm>
#include <cmath>

#include "reference/sampling.h"

namespace pcl {
namespace {

float channelTransmittance(float sigmaT, float distance) { return sigmaT > 0.0f ? std::exp(-sigmaT * distance) : 1.0f; }

}  // namespace

Vec3 transmittance(Vec3 sigmaT, float distance) {
    return {channelTransmittance(sigmaT.x, distance), channelTransmittance(sigmaT.y, distance),
            channelTransmittance(sigmaT.z, distance)};
}

FreeFlight sampleFreeFlight(const Medium& medium, float tMax, float u) {
    const Vec3 sigmaT = medium.sigmaT();
    const int channel = std::min(2, static_cast<int>(u * 3.0f));
    const float uDistance = std::min(u * 3.0f - static_cast<float>(channel), 0x1.fffffep-1f);
    const float sigmaC = sigmaT[channel];
    FreeFlight f;
    f.t = sigmaC > 0.0f ? -std::log1p(-uDistance) / sigmaC : std::numeric_limits<float>::infinity();
    if (f.t < tMax) {
        // A scattering event: density (1/3) Σ_c σt[c] e^{−σt[c] t}.
        f.scattered = true;
        const Vec3 tr = transmittance(sigmaT, f.t);
        const float pdf = dot(sigmaT * tr, Vec3(1.0f)) / 3.0f;
        f.weight = pdf > 0.0f ? medium.sigmaS * tr / pdf : Vec3(0.0f);
        return f;
    }
    // Past the segment's end: probability (1/3) Σ_c e^{−σt[c] tMax}.
    f.t = tMax;
    const Vec3 tr = transmittance(sigmaT, tMax);
    const float probability = dot(tr, Vec3(1.0f)) / 3.0f;
    f.weight = probability > 0.0f ? tr / probability : Vec3(0.0f);
    return f;
}

float henyeyGreenstein(float cosScatter, float g) {
    const float denom = 1.0f + g * g - 2.0f * g * cosScatter;
    return (1.0f - g * g) / (4.0f * kPi * denom * std::sqrt(std::max(denom, 0.0f)));
}

float sampleHenyeyGreensteinCosine(float g, float u) {
    if (std::abs(g) < 1e-3f) return 1.0f - 2.0f * u;
    const float s = (1.0f - g * g) / (1.0f - g + 2.0f * g * u);
    return std::clamp((1.0f + g * g - s * s) / (2.0f * g), -1.0f, 1.0f);
}

Vec3 sampleHenyeyGreenstein(Vec3 wo, float g, float u1, float u2) {
    const float cosTheta = sampleHenyeyGreensteinCosine(g, u1);
    const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    const Vec3 forward = -wo;
    Vec3 t, b;
    makeBasis(forward, t, b);
    return fromLocal(t, b, forward, sinTheta, cosTheta, 2.0f * kPi * u2);
}

}  // namespace pcl
