// The fixed-radius irradiance estimate of progressive photon mapping (Knaus & Zwicker 2011) from
// a k-nearest one: the box-filtered sum of the photons within radius r divided by π r², not by
// the area out to the k-th photon. With the box filter and k = maxK, a search that returns fewer
// than k photons found every photon within r, and E_box · r_found² / r² is exactly the
// fixed-radius sum; one that returns k (a disc holding more) keeps the k-nearest estimate.
// Host code, shared by the device's reader (render/fixed_radius_source.h) and the twin's.
#pragma once
#include <algorithm>
#include <cstdint>

#include "shared/types.h"

namespace pcl {

// Rescales `e` (the box estimate at query q, searched with k = min(q.k, maxK)) to the disc of
// radius² min(q.maxRadius2, radius2).
inline void rescaleToFixedRadius(PclEstimate& e, const PclEstimateQuery& q, uint32_t maxK, float radius2) {
    const float r2 = std::min(q.maxRadius2, radius2);
    const uint32_t k = std::min(q.k, maxK);
    if (e.found < k && e.radius2 > 0.0f && r2 > 0.0f) {
        const float scale = e.radius2 / r2;
        e.r *= scale;
        e.g *= scale;
        e.b *= scale;
        e.radius2 = r2;
    }
}

}  // namespace pcl
