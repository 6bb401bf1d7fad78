#include "reference/precomputed_irradiance.h"

#include <cmath>

#include "reference/estimate.h"
#include "reference/parallel_for.h"
#include "shared/sampling.h"

namespace pcl {

std::vector<PclIrradiancePoint> referenceSelectIrradiancePoints(const std::vector<PclPhoton>& map, uint32_t every) {
    std::vector<PclIrradiancePoint> points;
    if (every == 0) return points;
    for (size_t i = 0; i < map.size(); i += every) {
        PclIrradiancePoint s{};
        s.x = map[i].x, s.y = map[i].y, s.z = map[i].z;
        s.normal = map[i].normal;
        s.photon = uint32_t(i);
        points.push_back(s);
    }
    return points;
}

void referenceDecodeNormal(uint32_t word, float n[3]) {
    float u = float(int16_t(word & 0xFFFFu)) / 32767.0f;
    float v = float(int16_t(word >> 16)) / 32767.0f;
    const float z = 1.0f - std::fabs(u) - std::fabs(v);
    if (z < 0.0f) {
        const float fu = (1.0f - std::fabs(v)) * (u >= 0.0f ? 1.0f : -1.0f);
        v = (1.0f - std::fabs(u)) * (v >= 0.0f ? 1.0f : -1.0f);
        u = fu;
    }
    const float l = std::sqrt(u * u + v * v + z * z);
    n[0] = u / l, n[1] = v / l, n[2] = z / l;
}

PclEstimateQuery referenceIrradianceEstimateQuery(const PclIrradiancePoint& point, float maxRadius2, uint32_t k) {
    PclEstimateQuery q{};
    float n[3];
    referenceDecodeNormal(point.normal, n);
    q.x = point.x, q.y = point.y, q.z = point.z;
    q.maxRadius2 = maxRadius2;
    q.nx = n[0], q.ny = n[1], q.nz = n[2];
    q.k = k;
    return q;
}

void referenceEstimateIrradiancePoints(const std::vector<PclPhoton>& map, std::vector<PclIrradiancePoint>& points,
                                       const PrecomputedIrradianceOptions& options, const SceneGeometry* geometry,
                                       unsigned threads, std::vector<float>* cover, std::vector<float>* nondirect) {
    // The others: every photon whose index is not a multiple of m, in map order.
    std::vector<PclPhoton> others;
    for (size_t i = 0; i < map.size(); ++i)
        if (i % options.every != 0) others.push_back(map[i]);
    std::vector<PclEstimateQuery> queries;
    queries.reserve(points.size());
    const float maxRadius2 = options.maxRadius * options.maxRadius;
    for (const PclIrradiancePoint& p : points)
        queries.push_back(referenceIrradianceEstimateQuery(p, maxRadius2, options.k));
    const std::vector<PclEstimate> e = referenceEstimate(others, queries, options.estimate, geometry, threads);
    const float scale = float(options.every) / float(options.every - 1);
    for (size_t j = 0; j < points.size(); ++j)
        points[j].r = e[j].r * scale, points[j].g = e[j].g * scale, points[j].b = e[j].b * scale;
    if (cover) {
        cover->resize(points.size());
        const float f2 = options.coverFactor * options.coverFactor;
        for (size_t j = 0; j < points.size(); ++j) (*cover)[j] = std::isinf(f2) ? INFINITY : f2 * e[j].radius2;
    }
    if (nondirect) {
        nondirect->assign(points.size() * 4, 0.0f);
        for (size_t j = 0; j < points.size(); ++j) {
            float c[3];
            photon_rgbe_decode(e[j].nondirect, &c[0], &c[1], &c[2]);
            for (int i = 0; i < 3; ++i) (*nondirect)[4 * j + i] = c[i] * scale;
        }
    }
}

std::vector<PclIrradiancePoint> referencePrecomputeIrradiance(const std::vector<PclPhoton>& map,
                                                              const PrecomputedIrradianceOptions& options,
                                                              const SceneGeometry* geometry, unsigned threads,
                                                              std::vector<float>* cover,
                                                              std::vector<float>* nondirect) {
    std::vector<PclIrradiancePoint> points = referenceSelectIrradiancePoints(map, options.every);
    referenceEstimateIrradiancePoints(map, points, options, geometry, threads, cover, nondirect);
    return points;
}

ReferenceIrradianceLookup referenceLookupIrradiance(const std::vector<PclIrradiancePoint>& points,
                                                    const std::vector<float>& cover,
                                                    const std::vector<PclEstimateQuery>& queries, float minNormalCos,
                                                    unsigned threads, const std::vector<float>& nondirect) {
    ReferenceIrradianceLookup r;
    r.irradiance.assign(queries.size() * 4, 0.0f);
    r.chosen.assign(queries.size(), PCL_NO_HIT);
    // Decoded once: the lookup compares each point's normal with every query's.
    std::vector<float> normals(points.size() * 3);
    for (size_t i = 0; i < points.size(); ++i) referenceDecodeNormal(points[i].normal, &normals[3 * i]);
    referenceParallelFor(queries.size(), threads, [&](size_t qi) {
        const PclEstimateQuery& q = queries[qi];
        float bestD2 = 0.0f;
        uint32_t bestPhoton = PCL_NO_HIT;
        size_t best = 0;
        for (size_t i = 0; i < points.size(); ++i) {
            const PclIrradiancePoint& p = points[i];
            const float dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
            const float xy = dx * dx + dy * dy;
            const float d2 = xy + dz * dz;
            if (!(d2 <= q.maxRadius2)) continue;
            if (!cover.empty() && !(d2 <= cover[i])) continue;
            const uint32_t photon = p.photon & PCL_IRRADIANCE_INDEX_MASK;
            if (bestPhoton != PCL_NO_HIT && (d2 > bestD2 || (d2 == bestD2 && photon > bestPhoton))) continue;
            const float* n = &normals[3 * i];
            const float nxy = n[0] * q.nx + n[1] * q.ny;
            if (!(nxy + n[2] * q.nz >= minNormalCos)) continue;
            bestD2 = d2, bestPhoton = photon, best = i;
        }
        if (bestPhoton == PCL_NO_HIT) return;
        r.chosen[qi] = bestPhoton;
        const bool later = (q.k & PCL_QUERY_NONDIRECT) && !nondirect.empty();
        r.irradiance[4 * qi + 0] = later ? nondirect[4 * best + 0] : points[best].r;
        r.irradiance[4 * qi + 1] = later ? nondirect[4 * best + 1] : points[best].g;
        r.irradiance[4 * qi + 2] = later ? nondirect[4 * best + 2] : points[best].b;
        r.irradiance[4 * qi + 3] = bestD2;
    });
    return r;
}

}  // namespace pcl
