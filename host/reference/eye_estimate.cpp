#include "reference/eye_estimate.h"

#include <cmath>

#include "reference/sampling.h"
#include "reference/shutter_open.h"

namespace pcl {

std::vector<PclEstimateQuery> referenceEyeEstimateQueries(const std::vector<PclEyeHit>& hits,
                                                          const PclEyeEstimateParams& params,
                                                          const std::vector<PclPrimInfo>& primInfo) {
    std::vector<PclEstimateQuery> q(hits.size());
    for (size_t i = 0; i < hits.size(); ++i) {
        const PclEyeHit& h = hits[i];
        q[i] = PclEstimateQuery{};
        q[i].k = params.k;
        q[i].nz = 1.0f;
        if ((h.flags & PCL_EYE_DIFFUSE) && h.depth >= params.minDepth) {
            Vec3 p(h.x, h.y, h.z);
            if (params.atShutterOpen) p = shutterOpenPosition(primInfo.at(h.prim), p, h.time);
            q[i].x = p.x;
            q[i].y = p.y;
            q[i].z = p.z;
            q[i].nx = h.nx;
            q[i].ny = h.ny;
            q[i].nz = h.nz;
            q[i].maxRadius2 = params.maxRadius2;
        }
    }
    return q;
}

std::vector<PclRadiance> referenceEyeEstimateResolve(const std::vector<PclEyeHit>& hits,
                                                     const std::vector<Vec3>& irradiance) {
    std::vector<PclRadiance> out(hits.size());
    for (size_t i = 0; i < hits.size(); ++i) {
        const PclEyeHit& h = hits[i];
        out[i] = PclRadiance{};
        if (!(h.flags & PCL_EYE_DIFFUSE)) continue;
        const float E[3] = {irradiance[i].x, irradiance[i].y, irradiance[i].z};
        float L3[3];
        for (int c = 0; c < 3; ++c) {
            L3[c] = h.throughput[c] * h.albedo[c] * E[c] / kPi;
            if (!std::isfinite(L3[c])) L3[c] = 0.0f;
        }
        out[i] = PclRadiance{L3[0], L3[1], L3[2], 0.0f};
    }
    return out;
}

std::vector<PclRadiance> referenceEstimateAtEyeHits(const std::vector<PclEyeHit>& hits,
                                                    const PclEyeEstimateParams& params,
                                                    const std::vector<PclPrimInfo>& primInfo,
                                                    const ReferenceIrradiance& irradiance) {
    return referenceEyeEstimateResolve(hits, irradiance(referenceEyeEstimateQueries(hits, params, primInfo)));
}

}  // namespace pcl
