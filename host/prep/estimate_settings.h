// The settings of the irradiance estimate (kernels/README.md, "estimate"; Jensen 2001 §7.2),
// read alike by the kernel's host side (pipeline/estimate) and the CPU twin
// (reference/estimate):
//   E = Σ_p w(d_p/r) ΔΦ_p / (norm · π r²),   r² = the squared distance to the k-th photon,
// over the photons that pass the rejection tests (arrived from the shaded side, a surface
// facing the same way, optionally an unoccluded lifted segment). The filter's norm is defined
// here once, so both sides divide by the same number.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "prep/knn_structure.h"
#include "shared/types.h"

namespace pcl {

enum class EstimateFilter { Box, Cone, Epanechnikov, Gaussian };

const char* estimateFilterName(EstimateFilter f);  // "box", "cone", "epanechnikov", "gaussian"
// The filter named `name` (one of the above); InputError listing the valid names otherwise.
EstimateFilter parseEstimateFilter(const std::string& name);
// Every filter, in enum order.
const std::vector<EstimateFilter>& allEstimateFilters();
uint32_t estimateFilterCode(EstimateFilter f);  // PCL_FILTER_*

struct EstimateSettings {
    EstimateFilter filter = EstimateFilter::Cone;
    float coneK = 1.1f;                             // cone: k_c ≥ 1 (w = 1 − d/(k_c r))
    float minNormalCos = 0.9f;                      // a photon counts when n_p·n_q ≥ this
    bool visibility = false;                        // reject photons whose lifted segment to the query is occluded
                                                    // (needs the scene: DeviceScene / SceneGeometry)
    float rayEpsilon = 1e-6f;                       // visibility lift h = rayEpsilon + 0.25 r: SceneBuffers::rayEpsilon
    KnnStructure structure = KnnStructure::KdTree;  // the map structure precomputeIrradiance builds
                                                    // (and estimateOnDevice, check/on_device.h)
    // A first kNN search bound (kd-tree): a guess of the k-th photon's d² (firstSearchRadius2);
    // queries finding fewer search again without it. Speed only: the estimates are the same.
    float firstRadius2 = INFINITY;
};

// A first search bound for k-nearest queries in a map of `photons` over `area` m² of surface: 9×
// the disc that holds k photons at the mean density (∞ when either is 0).
float firstSearchRadius2(size_t photons, uint32_t k, double area);

// InternalError when coneK < 1 or not finite, minNormalCos is NaN or rayEpsilon is negative/NaN.
void validateEstimateSettings(const EstimateSettings& s);

// The filter's normalisation: the mean of w over the unit disc, 2∫₀¹ w(u) u du (double):
// box 1; cone 1 − 2/(3 k_c); Epanechnikov 1/2; Gaussian 1 − [1 − (2/β)(1 − e^{−β/2})]/(1 − e^{−β}).
double estimateFilterNorm(EstimateFilter f, float coneK);
// 1 / (1 − e^{−β}), β = PCL_GAUSSIAN_BETA (double).
double estimateGaussianScale();

// The kernel's parameters for a batch (norm and gaussianScale rounded to float).
PclEstimateParams estimateParams(const EstimateSettings& s, uint32_t firstQuery, uint32_t queryCount, uint32_t stride);

// Largest k over the queries; InternalError when a k is outside 1..PCL_KNN_MAX_K, a radius is
// negative or NaN, or a normal is not finite.
uint32_t estimateMaxK(const std::vector<PclEstimateQuery>& queries);

}  // namespace pcl
