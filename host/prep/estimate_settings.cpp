#include "prep/estimate_settings.h"

#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/math.h"

namespace pcl {
namespace {

// The visibility test lifts both ends of its segment by rayEpsilon + this fraction of r, so a
// curved surface does not shadow its own photons.
constexpr float kLiftFraction = 0.25f;

}  // namespace

const char* estimateFilterName(EstimateFilter f) {
    switch (f) {
        case EstimateFilter::Box: return "box";
        case EstimateFilter::Cone: return "cone";
        case EstimateFilter::Epanechnikov: return "epanechnikov";
        case EstimateFilter::Gaussian: return "gaussian";
    }
    return "?";
}

const std::vector<EstimateFilter>& allEstimateFilters() {
    static const std::vector<EstimateFilter> all = {EstimateFilter::Box, EstimateFilter::Cone,
                                                    EstimateFilter::Epanechnikov, EstimateFilter::Gaussian};
    return all;
}

EstimateFilter parseEstimateFilter(const std::string& name) {
    for (EstimateFilter f : allEstimateFilters())
        if (name == estimateFilterName(f)) return f;
    throw InputError("estimate: unknown filter \"" + name + "\", expected one of box|cone|epanechnikov|gaussian");
}

uint32_t estimateFilterCode(EstimateFilter f) {
    switch (f) {
        case EstimateFilter::Box: return PCL_FILTER_BOX;
        case EstimateFilter::Cone: return PCL_FILTER_CONE;
        case EstimateFilter::Epanechnikov: return PCL_FILTER_EPANECHNIKOV;
        case EstimateFilter::Gaussian: return PCL_FILTER_GAUSSIAN;
    }
    return PCL_FILTER_BOX;
}

void validateEstimateSettings(const EstimateSettings& s) {
    if (std::isnan(s.firstRadius2) || s.firstRadius2 < 0.0f)
        throw InternalError("estimate: first search radius² " + std::to_string(s.firstRadius2) + ": expected ≥ 0 or ∞");
    if (!(s.coneK >= 1.0f) || !std::isfinite(s.coneK))
        throw InternalError("estimate: cone filter k = " + std::to_string(s.coneK) + ", expected a finite k ≥ 1");
    if (std::isnan(s.minNormalCos)) throw InternalError("estimate: minNormalCos is NaN, expected a cosine in [-1, 1]");
    if (!(s.rayEpsilon >= 0.0f) || !std::isfinite(s.rayEpsilon))
        throw InternalError("estimate: rayEpsilon = " + std::to_string(s.rayEpsilon) + ", expected a finite value ≥ 0");
}

PclEstimateParams estimateParams(const EstimateSettings& s, uint32_t firstQuery, uint32_t queryCount, uint32_t stride) {
    PclEstimateParams p{};
    p.filter = estimateFilterCode(s.filter);
    p.coneK = s.coneK;
    p.norm = float(estimateFilterNorm(s.filter, s.coneK));
    p.gaussianScale = float(estimateGaussianScale());
    p.minNormalCos = s.minNormalCos;
    p.visibility = s.visibility ? 1u : 0u;
    p.rayEpsilon = s.rayEpsilon;
    p.liftFraction = kLiftFraction;
    p.firstQuery = firstQuery;
    p.queryCount = queryCount;
    p.stride = stride;
    p.maxSearchRadius2 = std::numeric_limits<float>::infinity();
    return p;
}

double estimateFilterNorm(EstimateFilter f, float coneK) {
    switch (f) {
        case EstimateFilter::Box: return 1.0;
        case EstimateFilter::Cone: return 1.0 - 2.0 / (3.0 * double(coneK));
        case EstimateFilter::Epanechnikov: return 0.5;
        case EstimateFilter::Gaussian: {
            const double beta = double(PCL_GAUSSIAN_BETA);
            return 1.0 - (1.0 - (2.0 / beta) * (1.0 - std::exp(-beta / 2.0))) / (1.0 - std::exp(-beta));
        }
    }
    return 1.0;
}

double estimateGaussianScale() { return 1.0 / (1.0 - std::exp(-double(PCL_GAUSSIAN_BETA))); }

uint32_t estimateMaxK(const std::vector<PclEstimateQuery>& queries) {
    uint32_t maxK = 1;
    for (size_t i = 0; i < queries.size(); ++i) {
        const PclEstimateQuery& q = queries[i];
        const uint32_t k = q.k & ~PCL_QUERY_NONDIRECT;
        if (k == 0 || k > PCL_KNN_MAX_K)
            throw InternalError("estimate: query " + std::to_string(i) + " asks k = " + std::to_string(k) +
                                ", expected 1.." + std::to_string(PCL_KNN_MAX_K));
        if (!(q.maxRadius2 >= 0.0f))
            throw InternalError("estimate: query " + std::to_string(i) +
                                " has maxRadius2 = " + std::to_string(q.maxRadius2) + ", expected ≥ 0");
        if (!std::isfinite(q.nx) || !std::isfinite(q.ny) || !std::isfinite(q.nz))
            throw InternalError("estimate: query " + std::to_string(i) +
                                " has a non-finite normal, expected a unit vector");
        maxK = std::max(maxK, k);
    }
    return maxK;
}

float firstSearchRadius2(size_t photons, uint32_t k, double area) {
    if (photons == 0 || k == 0 || !(area > 0.0) || !std::isfinite(area)) return INFINITY;
    return float(9.0 * double(k) * area / (kPiD * double(photons)));
}

}  // namespace pcl
