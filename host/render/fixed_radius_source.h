// A fixed-radius irradiance estimate for progressive photon mapping (Knaus & Zwicker 2011): the
// box-filtered sum of the photons within radius r divided by π r², not by the area out to the
// k-th photon. Built on the k-nearest-neighbour estimate (pipeline/estimate.h) with the box
// filter and k = maxK: where the search returns fewer than maxK photons it found every photon
// within r, and E_box · r_found² / r² is exactly the fixed-radius sum; where it returns maxK
// (a disc holding more than maxK photons) the k-nearest estimate is kept as it is.
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
