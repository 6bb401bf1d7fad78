#include "prep/irradiance_settings.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace pcl {

void validatePrecomputedIrradianceOptions(const PrecomputedIrradianceOptions& o) {
    if (o.every < 2)  // the estimates search the photons not selected: there must be some
        throw InternalError("precomputed irradiance: every = " + std::to_string(o.every) +
                            ", expected a photon step ≥ 2");
    if (!(o.coverFactor > 0.0f))
        throw InternalError("precomputed irradiance: coverFactor = " + std::to_string(o.coverFactor) +
                            ", expected a positive factor (or infinity)");
    if (o.k == 0 || o.k > PCL_KNN_MAX_K)
        throw InternalError("precomputed irradiance: k = " + std::to_string(o.k) + ", expected 1.." +
                            std::to_string(PCL_KNN_MAX_K));
    if (!(o.maxRadius > 0.0f) || !std::isfinite(o.maxRadius))
        throw InternalError("precomputed irradiance: maxRadius = " + std::to_string(o.maxRadius) +
                            ", expected a positive finite radius");
    validateEstimateSettings(o.estimate);
}

}  // namespace pcl
