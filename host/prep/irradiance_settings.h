// The settings of Christensen's precomputed irradiance (pipeline/precomputed_irradiance.h has
// the method and why the estimates search the other photons), read alike by the device stage
// and its twin (reference/precomputed_irradiance).
#pragma once
#include <cstdint>

#include "prep/estimate_settings.h"

namespace pcl {

struct PrecomputedIrradianceOptions {
    uint32_t every = 4;         // m ≥ 2: photons 0, m, 2m, … of the global map get a stored point
    uint32_t k = 50;            // photons per estimate at a stored point (from the other photons)
    float maxRadius = 0.0f;     // those estimates' r_max
    float coverFactor = 2.0f;   // f: a point answers queries within f × its estimate's radius (∞: any)
    EstimateSettings estimate;  // filter, normal test, visibility, structure of the others' map;
                                // estimate.minNormalCos is also the lookup's normal threshold
};

// InternalError when every < 2, coverFactor is not positive (or NaN), k is outside 1..PCL_KNN_MAX_K, maxRadius is not positive and
// finite, or the estimate settings are invalid.
void validatePrecomputedIrradianceOptions(const PrecomputedIrradianceOptions& o);

}  // namespace pcl
