// Homogeneous participating media for the reference path tracer: transmittance, free-flight
// distance sampling and the Henyey–Greenstein phase function (pbrt-v4 ch. 11; pbrt-v3 §15.2).
//
// Distances are sampled per colour channel: one channel c is picked with probability P(c)
// proportional to the path's throughput β in it, and t drawn from σt[c] e^{−σt[c] t}; the
// density in the weights is the mixture Σ_c P(c) σt[c] e^{−σt[c] t} (the one-sample balance
// heuristic over channels, "spectral MIS"), so a medium whose σt differs per channel stays
// unbiased in every channel. Choosing by throughput keeps the weights bounded along the whole
// path: the new throughputs β[c] σs[c] Tr[c] Σβ / Σ_i β[i] σt[i] Tr[i] never sum to more than
// Σβ (with uniform choice, products of per-event weights up to 3 gave heavy-tailed pixels in a
// chromatic furnace). Homogeneous media need no delta tracking: transmittance is analytic.
#pragma once
#include <limits>

#include "core/vec3.h"
#include "scene/scene.h"

namespace pcl {

// exp(−σt d) per channel; a channel with σt = 0 transmits 1 at any distance (even infinite).
Vec3 transmittance(Vec3 sigmaT, float distance);

struct FreeFlight {
    bool scattered = false;  // true: a scattering event at distance t; false: the segment's end reached
    float t = std::numeric_limits<float>::infinity();
    // The factor on the path throughput: σs Tr(t) / p(t) for a scattering event, Tr(tMax) /
    // P(t ≥ tMax) for the end of the segment. Zero when the sample cannot carry weight (escape to
    // infinity, or a throughput of zero).
    Vec3 weight{0.0f};
};

// Samples the distance to the next scattering event along a segment of length tMax (infinite
// when the ray leaves the scene) inside `medium`, for a path of throughput `beta`, from one
// uniform number u in [0, 1): where it falls among the channels' probabilities picks the
// channel, its place within that share (rescaled to [0, 1)) the distance t = −ln(1 − u′)/σt[c].
FreeFlight sampleFreeFlight(const Medium& medium, float tMax, float u, Vec3 beta);
// The same from two numbers, one for the channel and one for the distance (the photon pass,
// kernels/shared/medium.h): the distance then depends on uDistance alone, not on the last bits
// of the channel probabilities, so a kernel and its twin whose powers differ by an ulp still
// place a long flight's end at the same point (one number: 1 − u′ near 0 amplifies them).
FreeFlight sampleFreeFlight(const Medium& medium, float tMax, float uChannel, float uDistance, Vec3 beta);

// The density sampleFreeFlight gives a scattering event at distance t < tMax for a path of
// throughput beta: Σ_c P(c) σt[c] e^{−σt[c] t} (0 when beta carries nothing).
float freeFlightPdf(const Medium& medium, float t, Vec3 beta);

// Equiangular sampling (Kulla & Fajardo 2012) of a distance t in [0, tMax] along the ray
// origin + t dir (dir unit, tMax may be infinite) toward the point `light`: uniform in the angle
// the light subtends, p(t) = D / ((θb − θa)(D² + (t − Δ)²)) with Δ the light's projection on the
// ray and D its distance from it, which cancels the 1/r² of a point light's irradiance. False
// when the light lies on the ray's line (D = 0) or the interval is empty.
bool sampleEquiangular(Vec3 origin, Vec3 dir, float tMax, Vec3 light, float u, float& t, float& pdf);
// Its density at t (0 where sampleEquiangular would return false or t is outside [0, tMax]).
float equiangularPdf(Vec3 origin, Vec3 dir, float tMax, Vec3 light, float t);

// Henyey–Greenstein phase function (Henyey & Greenstein 1941) of the scattering angle's cosine
// μ (between the direction of travel before and after; g > 0 scatters forward):
//   p(μ) = (1 − g²) / (4π (1 + g² − 2gμ)^{3/2}),   ∫ p dω = 1,   E[μ] = g.
float henyeyGreenstein(float cosScatter, float g);

// A direction wi drawn from p(μ) around the forward direction −wo (wo points back along the
// incoming ray, wi away from the scattering point, as for BSDFs). The density (solid angle) is
// henyeyGreenstein(dot(−wo, wi), g); the sample's weight p/pdf is exactly 1.
Vec3 sampleHenyeyGreenstein(Vec3 wo, float g, float u1, float u2);

// The cosine μ of the scattering angle sampled from u by inverting the HG distribution
// (pbrt-v3 eq. 15.7), increasing in u; μ = 2u − 1 for |g| < 1e-3, where the formula loses precision.
float sampleHenyeyGreensteinCosine(float g, float u);

}  // namespace pcl
