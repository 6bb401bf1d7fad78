/* medium.h: homogeneous participating media for the photon pass (kernels/README.md,
 * "trace_photons", media). The twin is host/reference/medium.cpp, written independently.
 *
 *   medium_free_flight  distance to the next scattering event along a segment, chosen per colour
 *                       channel in proportion to the photon's power ("spectral MIS", pbrt-v4
 *                       §14.2.2), and the factor on the power: σs Tr(t)/p(t) at a scattering event
 *                       (the power scattered there), Tr(tMax)/P(t ≥ tMax) at the segment's end.
 *                       p(t) = Σ_c P(c) σt[c] e^{−σt[c] t} with P(c) = Φ[c]/ΣΦ: the new powers never
 *                       sum to more than the old (Σ_c Φ[c] σs[c] Tr[c] / Σ_c Φ[c] σt[c] Tr[c] ≤ 1),
 *                       so a chromatic medium keeps photon power bounded where a channel-averaged
 *                       σt would let weights grow along a path.
 *   medium_hg_cos       cosine of a Henyey–Greenstein scattering angle by inversion (pbrt-v3 eq. 15.7)
 *
 * Arithmetic left to right in the order of host/reference/medium.cpp (FP_CONTRACT off on the
 * device), so the twin's floats differ only by the library's exp/log1p rounding. */
#ifndef PCL_MEDIUM_H
#define PCL_MEDIUM_H

#include "compat.h"
#include "types.h"

#if PCL_DEVICE
  #define PCL_EXPF(x) exp(x)
  #define PCL_LOG1PF(x) log1p(x)
#else
  #define PCL_EXPF(x) expf(x)
  #define PCL_LOG1PF(x) log1pf(x)
#endif

PCL_INLINE pcl_f32 medium_channel_tr(pcl_f32 sigmaT, pcl_f32 distance) {
    return sigmaT > 0.0f ? PCL_EXPF(-sigmaT * distance) : 1.0f;
}

/* uChannel in [0, 1): the share it falls in picks the channel; uDistance the distance (two
 * numbers, so the distance does not inherit the last bits of the powers, which kernel and twin
 * may round differently: with one number rescaled within its share, a long flight (1 − u′ near
 * 0) amplified an ulp of the powers to 1e-4 of its length). Returns 1 for a scattering event at *t (< tMax), 0 for
 * the segment's end (*t = tMax); weight[c] multiplies the power (all 0 when the power is 0 or
 * the photon leaves to infinity). */
PCL_INLINE int medium_free_flight(PclMedium m, pcl_f32 tMax, pcl_f32 uChannel, pcl_f32 uDistance,
                                  const pcl_f32 phi[3], pcl_f32* t,
                                  pcl_f32 weight[3]) {
    weight[0] = weight[1] = weight[2] = 0.0f;
    *t = INFINITY;
    pcl_f32 P[3];
    for (int c = 0; c < 3; ++c) P[c] = phi[c] > 0.0f ? phi[c] : 0.0f;
    const pcl_f32 total = P[0] + P[1] + P[2];
    if (!(total > 0.0f) || !isfinite(total)) return 0;
    const pcl_f32 inv = 1.0f / total;
    for (int c = 0; c < 3; ++c) P[c] = P[c] * inv;
    int channel = 0;
    pcl_f32 below = 0.0f;
    while (channel < 2 && (P[channel] == 0.0f || uChannel >= below + P[channel])) {
        below += P[channel];
        ++channel;
    }
    while (P[channel] == 0.0f) --channel;
    pcl_f32 uD = uDistance;
    uD = uD < 0.0f ? 0.0f : (uD > 0x1.fffffep-1f ? 0x1.fffffep-1f : uD);
    pcl_f32 sigmaT[3];
    for (int c = 0; c < 3; ++c) sigmaT[c] = m.sigmaA[c] + m.sigmaS[c];
    const pcl_f32 sc = sigmaT[channel];
    const pcl_f32 tc = sc > 0.0f ? -PCL_LOG1PF(-uD) / sc : INFINITY;
    pcl_f32 tr[3];
    if (tc < tMax) {
        *t = tc;
        for (int c = 0; c < 3; ++c) tr[c] = medium_channel_tr(sigmaT[c], tc);
        const pcl_f32 pdf = P[0] * (sigmaT[0] * tr[0]) + P[1] * (sigmaT[1] * tr[1]) + P[2] * (sigmaT[2] * tr[2]);
        if (pdf > 0.0f)
            for (int c = 0; c < 3; ++c) weight[c] = m.sigmaS[c] * tr[c] / pdf;
        return 1;
    }
    *t = tMax;
    for (int c = 0; c < 3; ++c) tr[c] = medium_channel_tr(sigmaT[c], tMax);
    const pcl_f32 prob = P[0] * tr[0] + P[1] * tr[1] + P[2] * tr[2];
    if (prob > 0.0f)
        for (int c = 0; c < 3; ++c) weight[c] = tr[c] / prob;
    return 0;
}

/* μ = cos of the angle between the directions before and after, E[μ] = g; 2u − 1 for |g| < 1e-3. */
PCL_INLINE pcl_f32 medium_hg_cos(pcl_f32 g, pcl_f32 u) {
    if (PCL_FABSF(g) < 1e-3f) return 2.0f * u - 1.0f;
    const pcl_f32 s = (1.0f - g * g) / (1.0f - g + 2.0f * g * u);
    const pcl_f32 mu = (1.0f + g * g - s * s) / (2.0f * g);
    return mu < -1.0f ? -1.0f : (mu > 1.0f ? 1.0f : mu);
}

#endif /* PCL_MEDIUM_H */
