#include "check/knn.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "check/camera_surface_hits.h"
#include "check/on_device.h"
#include "core/clock.h"
#include "pipeline/hashgrid.h"
#include "pipeline/kdtree.h"
#include "pipeline/photon_pass.h"
#include "prep/projection_map.h"

namespace pcl {
namespace {

constexpr double kDist2Tolerance = 1e-6;  // relative

PclKnnQuery makeQuery(float x, float y, float z, float maxRadius2, uint32_t k) {
    PclKnnQuery q{};
    q.x = x, q.y = y, q.z = z;
    q.maxRadius2 = maxRadius2;
    q.k = k;
    return q;
}

}  // namespace

bool KnnCheckRow::passed() const {
    return countMismatches == 0 && indexMismatches == 0 && radiusViolations == 0 && maxDist2Error <= kDist2Tolerance;
}

bool KnnCheckReport::passed() const {
    return !rows.empty() && std::all_of(rows.begin(), rows.end(), [](const auto& r) { return r.passed(); });
}

std::string KnnCheckReport::table() const {
    std::string out;
    char line[512];
    std::snprintf(line, sizeof line, "%-8s %-8s %-10s %4s %8s %7s %10s %6s %7s %7s %7s %10s %10s\n", "map", "queries",
                  "structure", "k", "photons", "queries", "neighbours", "empty", "count!=", "index!=", "r2 bad",
                  "max d2 err", "device s");
    out += line;
    for (const auto& r : rows) {
        std::snprintf(line, sizeof line, "%-8s %-8s %-10s %4u %8zu %7zu %10zu %6zu %7zu %7zu %7zu %10.2e %10.4f%s\n",
                      r.map.c_str(), r.queries.c_str(), r.structure.c_str(), r.k, r.photons, r.queryCount, r.neighbours,
                      r.empty, r.countMismatches, r.indexMismatches, r.radiusViolations, r.maxDist2Error,
                      r.deviceSeconds, r.passed() ? "" : "  FAIL");
        out += line;
    }
    std::snprintf(line, sizeof line,
                  "brute force %.2f s, device searches %.2f s, photon pass %.2f s; the device must return the brute "
                  "force's neighbours (same indices, same order), d² within %.0e relative, r² ≤ r_max² and r² = the "
                  "last d²\n",
                  bruteSeconds, deviceSeconds, photonSeconds, kDist2Tolerance);
    out += line;
    out += passed() ? "knn: passed\n" : "knn: FAILED\n";
    return out;
}

std::vector<PclKnnQuery> surfaceKnnQueries(const Scene& scene, const SceneGeometry& geometry, uint32_t count,
                                           float maxRadius, uint32_t k, uint64_t seed) {
    std::mt19937_64 rng(seed + 1);
    std::vector<PclKnnQuery> qs;
    for (const CameraSurfaceHit& h : cameraSurfaceHits(scene, geometry, count, seed))
        qs.push_back(makeQuery(h.p.x, h.p.y, h.p.z, randomQueryRadius2(rng, maxRadius), k));
    return qs;
}

std::vector<PclKnnQuery> randomKnnQueries(const float lo[3], const float hi[3], uint32_t count, float maxRadius,
                                          uint32_t k, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<PclKnnQuery> qs(count);
    for (auto& q : qs) {
        float p[3];
        for (int a = 0; a < 3; ++a) p[a] = lo[a] + u(rng) * (hi[a] - lo[a]);
        q = makeQuery(p[0], p[1], p[2], randomQueryRadius2(rng, maxRadius), k);
    }
    return qs;
}

void compareKnn(const std::vector<PclKnnQuery>& queries, const ReferenceKnn& brute, const KnnResult& device,
                KnnCheckRow& row) {
    row.queryCount += queries.size();
    const bool shapeOk = device.counts.size() == queries.size() && device.radius2.size() == queries.size() &&
                         device.indices.size() == queries.size() * size_t(device.stride) &&
                         device.dist2.size() == device.indices.size() && brute.counts.size() == queries.size();
    if (!shapeOk) {
        row.countMismatches += queries.size();
        return;
    }
    for (size_t qi = 0; qi < queries.size(); ++qi) {
        const PclKnnQuery& q = queries[qi];
        const uint32_t want = std::min(brute.counts[qi], q.k);
        const uint32_t got = device.counts[qi];
        row.neighbours += want;
        row.empty += want == 0;
        if (got != want || got > device.stride) {
            ++row.countMismatches;
            continue;
        }
        for (uint32_t j = 0; j < want; ++j) {
            const uint32_t bi = brute.indices[qi * brute.stride + j], di = device.indices[qi * device.stride + j];
            if (bi != di) {
                ++row.indexMismatches;
                continue;
            }
            const double b = brute.dist2[qi * brute.stride + j], d = device.dist2[qi * device.stride + j];
            const double err = std::fabs(b - d) / std::max(std::fabs(b), 1e-30);
            row.maxDist2Error = std::max(row.maxDist2Error, b == d ? 0.0 : err);
        }
        const float r2 = device.radius2[qi];
        const float last = got ? device.dist2[qi * device.stride + got - 1] : 0.0f;
        if (!(r2 <= q.maxRadius2) || r2 != last) ++row.radiusViolations;
    }
}

KnnCheckReport checkKnn(Device& device, const Scene& scene, const KnnCheckOptions& options) {
    const PreparedScene prepared = prepareScene(scene);
    return checkKnn(device, scene, prepared.geometry, prepared.buffers, options);
}

KnnCheckReport checkKnn(Device& device, const Scene& scene, const SceneGeometry& geometry, const SceneBuffers& buffers,
                        const KnnCheckOptions& options) {
    KnnCheckReport report;
    PhotonMaps maps =
        photonMapsOnDevice(device, geometry, buffers, options.photons, options.seed, &report.photonSeconds);
    auto t0 = Clock::now();

    const Bounds3 sb = geometry.bounds();
    const Vec3 ext = sb.extent();
    const float diagonal = std::sqrt(ext.x * ext.x + ext.y * ext.y + ext.z * ext.z);
    const float rMax = std::max(options.radiusFraction * diagonal, 1e-6f);
    uint32_t maxK = 1;
    for (uint32_t k : options.ks) maxK = std::max(maxK, k);

    const std::vector<PclKnnQuery> surface =
        surfaceKnnQueries(scene, geometry, options.surfaceQueries, rMax, maxK, options.seed * 7 + 1);
    for (const auto& [mapName, map] :
         {std::pair<const char*, const std::vector<PclPhoton>*>{"global", &maps.global}, {"caustic", &maps.caustic}}) {
        float lo[3] = {sb.lo.x, sb.lo.y, sb.lo.z}, hi[3] = {sb.hi.x, sb.hi.y, sb.hi.z};
        if (!map->empty()) {
            lo[0] = hi[0] = (*map)[0].x, lo[1] = hi[1] = (*map)[0].y, lo[2] = hi[2] = (*map)[0].z;
            for (const PclPhoton& p : *map) {
                const float c[3] = {p.x, p.y, p.z};
                for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
            }
        }
        for (int a = 0; a < 3; ++a) lo[a] -= rMax, hi[a] += rMax;
        const std::vector<PclKnnQuery> random =
            randomKnnQueries(lo, hi, options.randomQueries, rMax, maxK, options.seed * 7 + 2);
        // Each structure built once per map, searched for every query set and k.
        cl::Buffer photons = device.upload(*map, CL_MEM_READ_ONLY, "check knn: photon map");
        const KnnKdTree tree = packKdTree(device, buildKdTree(device, photons, map->size()));
        const DeviceHashGrid grid = buildHashGrid(device, photons, map->size(), hashGridParams(*map, rMax));
        for (const auto& [setName, base] :
             {std::pair<const char*, const std::vector<PclKnnQuery>*>{"random", &random}, {"surface", &surface}}) {
            t0 = Clock::now();
            const ReferenceKnn brute = referenceKnnBruteForce(*map, *base);
            report.bruteSeconds += since(t0);
            for (KnnStructure s : {KnnStructure::KdTree, KnnStructure::HashGrid})
                for (uint32_t k : options.ks) {
                    std::vector<PclKnnQuery> qs = *base;
                    for (auto& q : qs) q.k = k;
                    KnnCheckRow row;
                    row.map = mapName;
                    row.queries = setName;
                    row.structure = knnStructureName(s);
                    row.k = k;
                    row.photons = map->size();
                    // In query batches under the device's max allocation (--max-buffer-mib).
                    const KnnResult result = s == KnnStructure::KdTree ? knnSearchOnDevice(device, tree, qs)
                                                                       : knnSearchOnDevice(device, grid, qs);
                    row.deviceSeconds = result.searchSeconds;
                    report.deviceSeconds += row.deviceSeconds;
                    compareKnn(qs, brute, result, row);
                    report.rows.push_back(row);
                }
        }
    }
    return report;
}

}  // namespace pcl
