// Written from kernels/README.md, "estimate" (not from estimate.cl or shared/sampling.h).
#include "reference/estimate.h"

#include <cmath>

#include "core/error.h"
#include "core/math.h"
#include "reference/parallel_for.h"
#include "shared/sampling.h"

namespace pcl {
namespace {

struct V3 {
    float x, y, z;
};

float dot(V3 a, float bx, float by, float bz) { return a.x * bx + a.y * by + a.z * bz; }

// Incoming direction: the centre of the (θ, φ) byte cell; φ byte read as signed.
V3 decodeDirection(uint32_t packed) {
    const float theta = (float(packed & 255u) + 0.5f) * (kPi / 256.0f);
    const uint32_t pb = (packed >> 8) & 255u;
    const int32_t ps = pb >= 128u ? int32_t(pb) - 256 : int32_t(pb);
    const float phi = (float(ps) + 0.5f) * (kPi / 128.0f);
    const float st = std::sin(theta);
    return {st * std::cos(phi), st * std::sin(phi), std::cos(theta)};
}

// Octahedral snorm16 pair → unit normal.
V3 decodeNormal(uint32_t w) {
    float u = float(int32_t(int16_t(w & 0xFFFFu))) / 32767.0f;
    float v = float(int32_t(int16_t(w >> 16))) / 32767.0f;
    const float z = 1.0f - std::fabs(u) - std::fabs(v);
    if (z < 0.0f) {
        const float fu = (1.0f - std::fabs(v)) * (u >= 0.0f ? 1.0f : -1.0f);
        const float fv = (1.0f - std::fabs(u)) * (v >= 0.0f ? 1.0f : -1.0f);
        u = fu;
        v = fv;
    }
    const float l = std::sqrt(u * u + v * v + z * z);
    return {u / l, v / l, z / l};
}

void decodeRgbe(uint32_t rgbe, float c[3]) {
    const uint32_t e = rgbe >> 24;
    if (e == 0u) {
        c[0] = c[1] = c[2] = 0.0f;
        return;
    }
    const int x = int(e) - 136;
    c[0] = std::ldexp(float(rgbe & 255u), x);
    c[1] = std::ldexp(float((rgbe >> 8) & 255u), x);
    c[2] = std::ldexp(float((rgbe >> 16) & 255u), x);
}

}  // namespace

float referenceFilterWeight(const PclEstimateParams& p, float u2) {
    switch (p.filter) {
        case PCL_FILTER_CONE: return 1.0f - std::sqrt(u2) / p.coneK;
        case PCL_FILTER_EPANECHNIKOV: return 1.0f - u2;
        case PCL_FILTER_GAUSSIAN: return 1.0f - (1.0f - std::exp(u2 * (-0.5f * PCL_GAUSSIAN_BETA))) * p.gaussianScale;
        default: return 1.0f;
    }
}

PclEstimate referenceEstimateFromNeighbours(const std::vector<PclPhoton>& map, const PclEstimateQuery& q,
                                            const uint32_t* indices, const float* dist2, uint32_t count, float radius2,
                                            const EstimateSettings& settings, const SceneGeometry* geometry) {
    if (settings.visibility && !geometry)
        throw InternalError("estimate (reference): the visibility test needs the scene geometry, got none");
    const PclEstimateParams p = estimateParams(settings, 0, 1, count);
    float sum[3] = {0.0f, 0.0f, 0.0f}, later[3] = {0.0f, 0.0f, 0.0f};  // later: photons of bounce > 0
    uint32_t used = 0;
    const float r2 = radius2;
    if (r2 > 0.0f) {
        const float h = p.rayEpsilon + p.liftFraction * std::sqrt(r2);
        const float ax = q.x + h * q.nx, ay = q.y + h * q.ny, az = q.z + h * q.nz;
        for (uint32_t j = 0; j < count; ++j) {
            const PclPhoton& ph = map[indices[j]];
            if (!(dot(decodeDirection(ph.packed), q.nx, q.ny, q.nz) > 0.0f)) continue;
            const V3 n = decodeNormal(ph.normal);
            if (!(dot(n, q.nx, q.ny, q.nz) >= p.minNormalCos)) continue;
            if (p.visibility) {
                PclRay ray{};
                ray.ox = ax, ray.oy = ay, ray.oz = az, ray.tmin = 0.0f;
                ray.dx = (ph.x + h * n.x) - ax;
                ray.dy = (ph.y + h * n.y) - ay;
                ray.dz = (ph.z + h * n.z) - az;
                ray.tmax = 1.0f;
                ray.time = 0.0f;
                PclHit hit;
                if (geometry->intersect(ray, hit)) continue;
            }
            const float w = referenceFilterWeight(p, dist2[j] / r2);
            float c[3];
            decodeRgbe(ph.rgbe, c);
            for (int i = 0; i < 3; ++i) sum[i] += w * c[i];
            if (((ph.packed >> PCL_PHOTON_BOUNCE_SHIFT) & 255u) != 0u)
                for (int i = 0; i < 3; ++i) later[i] += w * c[i];
            ++used;
        }
    }
    PclEstimate e{};
    if (used > 0) {
        const float denom = (p.norm * kPi) * r2;
        const float* E = (q.k & PCL_QUERY_NONDIRECT) ? later : sum;
        e.r = E[0] / denom;
        e.g = E[1] / denom;
        e.b = E[2] / denom;
        e.nondirect = photon_rgbe_encode(later[0] / denom, later[1] / denom, later[2] / denom);
    }
    e.radius2 = r2;
    e.used = used;
    e.found = count;
    return e;
}

std::vector<PclKnnQuery> estimateKnnQueries(const std::vector<PclEstimateQuery>& queries) {
    std::vector<PclKnnQuery> out(queries.size());
    for (size_t i = 0; i < queries.size(); ++i) {
        const PclEstimateQuery& q = queries[i];
        out[i] = PclKnnQuery{q.x, q.y, q.z, q.maxRadius2, q.k & PCL_QUERY_K_MASK, 0, 0, 0};
    }
    return out;
}

std::vector<PclEstimate> referenceEstimateWithKnn(const std::vector<PclPhoton>& map,
                                                  const std::vector<PclEstimateQuery>& queries, const ReferenceKnn& knn,
                                                  const EstimateSettings& settings, const SceneGeometry* geometry,
                                                  unsigned threads) {
    validateEstimateSettings(settings);
    if (knn.counts.size() != queries.size())
        throw InternalError("estimate (reference): " + std::to_string(knn.counts.size()) + " kNN results for " +
                            std::to_string(queries.size()) + " queries");
    std::vector<PclEstimate> out(queries.size());
    referenceParallelFor(queries.size(), threads, [&](size_t i) {
        // The first k slots of a larger stride are the answer for k (the order is total).
        const uint32_t k = queries[i].k & PCL_QUERY_K_MASK;
        const uint32_t count = std::min(knn.counts[i], k);
        const size_t base = i * knn.stride;
        // Fewer than k found: the disc is the search radius's (as estimate.cl; the hash grid's own
        // limit is not known here, the query's radius is).
        const float cap2 = queries[i].maxRadius2;
        const float r2 = count == 0 ? 0.0f : count < k && std::isfinite(cap2) ? cap2 : knn.dist2[base + count - 1];
        out[i] = referenceEstimateFromNeighbours(map, queries[i], knn.indices.data() + base, knn.dist2.data() + base,
                                                 count, r2, settings, geometry);
    });
    return out;
}

std::vector<PclEstimate> referenceEstimate(const std::vector<PclPhoton>& map,
                                           const std::vector<PclEstimateQuery>& queries,
                                           const EstimateSettings& settings, const SceneGeometry* geometry,
                                           unsigned threads) {
    estimateMaxK(queries);
    const ReferenceKnn knn = referenceKnnBruteForce(map, estimateKnnQueries(queries), threads);
    return referenceEstimateWithKnn(map, queries, knn, settings, geometry, threads);
}

}  // namespace pcl
