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

namespace {

// The channel probabilities P (∝ max(β, 0)); false when β carries nothing.
bool channelProbabilities(Vec3 beta, Vec3& P) {
    const Vec3 choice = vmax(beta, Vec3(0.0f));
    const float total = choice.x + choice.y + choice.z;
    if (!(total > 0.0f) || !std::isfinite(total)) return false;
    P = choice / total;
    return true;
}

// The channel whose share of [0, 1) holds u; `below` receives the shares before it.
int pickChannel(const Vec3& P, float u, float& below) {
    int channel = 0;
    below = 0.0f;
    while (channel < 2 && (P[channel] == 0.0f || u >= below + P[channel])) {
        below += P[channel];
        ++channel;
    }
    while (P[channel] == 0.0f) --channel;  // rounding pushed u past the last share; total > 0 ends it
    return channel;
}

// t = −ln(1 − uDistance)/σt[channel], then the event's or the segment end's weight.
FreeFlight flight(const Medium& medium, float tMax, const Vec3& P, int channel, float uDistance) {
    FreeFlight f;
    const Vec3 sigmaT = medium.sigmaT();
    const float sigmaC = sigmaT[channel];
    f.t = sigmaC > 0.0f ? -std::log1p(-uDistance) / sigmaC : std::numeric_limits<float>::infinity();
    if (f.t < tMax) {
        // A scattering event: density Σ_c P(c) σt[c] e^{−σt[c] t}.
        f.scattered = true;
        const Vec3 tr = transmittance(sigmaT, f.t);
        const float pdf = dot(P, sigmaT * tr);
        f.weight = pdf > 0.0f ? medium.sigmaS * tr / pdf : Vec3(0.0f);
        return f;
    }
    // Past the segment's end: probability Σ_c P(c) e^{−σt[c] tMax}.
    f.t = tMax;
    const Vec3 tr = transmittance(sigmaT, tMax);
    const float probability = dot(P, tr);
    f.weight = probability > 0.0f ? tr / probability : Vec3(0.0f);
    return f;
}

}  // namespace

FreeFlight sampleFreeFlight(const Medium& medium, float tMax, float u, Vec3 beta) {
    Vec3 P;
    if (!channelProbabilities(beta, P)) return FreeFlight{};
    float below;
    const int channel = pickChannel(P, u, below);
    const float uDistance = std::clamp((u - below) / P[channel], 0.0f, 0x1.fffffep-1f);
    return flight(medium, tMax, P, channel, uDistance);
}

FreeFlight sampleFreeFlight(const Medium& medium, float tMax, float uChannel, float uDistance, Vec3 beta) {
    Vec3 P;
    if (!channelProbabilities(beta, P)) return FreeFlight{};
    float below;
    const int channel = pickChannel(P, uChannel, below);
    return flight(medium, tMax, P, channel, std::clamp(uDistance, 0.0f, 0x1.fffffep-1f));
}

float freeFlightPdf(const Medium& medium, float t, Vec3 beta) {
    Vec3 P;
    if (!channelProbabilities(beta, P)) return 0.0f;
    const Vec3 sigmaT = medium.sigmaT();
    return dot(P, sigmaT * transmittance(sigmaT, t));
}

namespace {

// The ray's closest approach to the light: Δ along the ray, D off it, and the angles of the
// interval's ends as seen from the light (θ = atan((t − Δ)/D)).
struct EquiangularFrame {
    float delta = 0.0f, D = 0.0f, thetaA = 0.0f, thetaB = 0.0f;
};

bool equiangularFrame(Vec3 origin, Vec3 dir, float tMax, Vec3 light, EquiangularFrame& f) {
    const Vec3 toLight = light - origin;
    f.delta = dot(toLight, dir);
    f.D = length(toLight - dir * f.delta);
    if (!(f.D > 1e-7f * std::max(1.0f, std::abs(f.delta))) || !(tMax > 0.0f)) return false;
    f.thetaA = std::atan2(-f.delta, f.D);
    f.thetaB = std::isinf(tMax) ? 0.5f * kPi : std::atan2(tMax - f.delta, f.D);
    return f.thetaB > f.thetaA;
}

}  // namespace

bool sampleEquiangular(Vec3 origin, Vec3 dir, float tMax, Vec3 light, float u, float& t, float& pdf) {
    EquiangularFrame f;
    if (!equiangularFrame(origin, dir, tMax, light, f)) return false;
    // θ stays below π/2 by a hair so tan θ is finite for an infinite segment.
    const float theta = std::min(f.thetaA + u * (f.thetaB - f.thetaA), 0.5f * kPi * 0x1.fffffep-1f);
    t = std::clamp(f.delta + f.D * std::tan(theta), 0.0f, tMax);
    const float x = t - f.delta;
    pdf = f.D / ((f.thetaB - f.thetaA) * (f.D * f.D + x * x));
    return pdf > 0.0f && std::isfinite(t);
}

float equiangularPdf(Vec3 origin, Vec3 dir, float tMax, Vec3 light, float t) {
    EquiangularFrame f;
    if (!(t >= 0.0f && t <= tMax) || !equiangularFrame(origin, dir, tMax, light, f)) return 0.0f;
    const float x = t - f.delta;
    return f.D / ((f.thetaB - f.thetaA) * (f.D * f.D + x * x));
}

float henyeyGreenstein(float cosScatter, float g) {
    const float denom = 1.0f + g * g - 2.0f * g * cosScatter;
    return (1.0f - g * g) / (4.0f * kPi * denom * std::sqrt(std::max(denom, 0.0f)));
}

float sampleHenyeyGreensteinCosine(float g, float u) {
    if (std::abs(g) < 1e-3f) return 2.0f * u - 1.0f;
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
