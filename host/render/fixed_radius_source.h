// The fixed-radius irradiance estimate of progressive photon mapping on the device: the
// k-nearest-neighbour estimate (pipeline/estimate.h) with the box filter and k = maxK, rescaled
// on the host by render/fixed_radius.h.
#pragma once
#include <memory>

#include "pipeline/estimate.h"
#include "pipeline/irradiance_source.h"

namespace pcl {

// `map` must outlive the source; settings.filter must be Box (InputError otherwise). Queries
// are answered with radius min(query maxRadius2, radius2) and k = min(query k, maxK). scene:
// needed when settings.visibility is on (as for estimateIrradianceSource).
std::shared_ptr<IrradianceSource> fixedRadiusSource(const PhotonMapOnDevice& map, uint32_t maxK,
                                                    const EstimateSettings& settings, float radius2,
                                                    const DeviceScene* scene = nullptr);

}  // namespace pcl
