#include "check/estimate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "check/camera_surface_hits.h"
#include "check/on_device.h"
#include "core/clock.h"
#include "pipeline/device_scene.h"
#include "pipeline/photon_pass.h"
#include "prep/projection_map.h"
#include "reference/estimate.h"
#include "shared/sampling.h"

namespace pcl {
namespace {

PclEstimateQuery makeQuery(Vec3 p, Vec3 n, float maxRadius2, uint32_t k) {
    PclEstimateQuery q{};
    q.x = p.x, q.y = p.y, q.z = p.z;
    q.nx = n.x, q.ny = n.y, q.nz = n.z;
    q.maxRadius2 = maxRadius2;
    q.k = k;
    return q;
}

std::vector<PclEstimateQuery> randomEstimateQueries(const float lo[3], const float hi[3], uint32_t count,
                                                    float maxRadius, uint32_t k, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<PclEstimateQuery> qs(count);
    for (auto& q : qs) {
        const Vec3 p(lo[0] + u(rng) * (hi[0] - lo[0]), lo[1] + u(rng) * (hi[1] - lo[1]),
                     lo[2] + u(rng) * (hi[2] - lo[2]));
        Vec3 n(g(rng), g(rng), g(rng));
        n = length(n) > 1e-6f ? normalize(n) : Vec3(0.0f, 0.0f, 1.0f);
        q = makeQuery(p, n, randomQueryRadius2(rng, maxRadius), k);
    }
    return qs;
}

bool finite(const PclEstimate& e) { return std::isfinite(e.r) && std::isfinite(e.g) && std::isfinite(e.b); }

}  // namespace

bool EstimateCheckRow::passed() const {
    return countMismatches == 0 && radiusMismatches == 0 && nans == 0 && maxRelError <= kEstimateTolerance &&
           nondirectError <= kNondirectTolerance;
}

bool EstimateCheckReport::passed() const {
    return !rows.empty() && std::all_of(rows.begin(), rows.end(), [](const auto& r) { return r.passed(); });
}

std::string EstimateCheckReport::table() const {
    std::string out;
    char line[512];
    std::snprintf(line, sizeof line, "%-8s %-8s %-10s %-13s %4s %8s %7s %7s %9s %7s %6s %4s %10s %10s %9s\n", "map",
                  "queries", "structure", "filter", "vis", "photons", "queries", "nonzero", "used",
                  "count!=", "r2!=", "nan", "max rel", "nondirect", "device s");
    out += line;
    for (const auto& r : rows) {
        std::snprintf(
            line, sizeof line, "%-8s %-8s %-10s %-13s %4s %8zu %7zu %7zu %9zu %7zu %6zu %4zu %10.2e %10.2e %9.4f%s\n",
            r.map.c_str(), r.queries.c_str(), r.structure.c_str(), r.filter.c_str(), r.visibility ? "on" : "off",
            r.photons, r.queryCount, r.nonzero, r.used, r.countMismatches, r.radiusMismatches, r.nans, r.maxRelError,
            r.nondirectError, r.deviceSeconds, r.passed() ? "" : "  FAIL");
        out += line;
    }
    std::snprintf(line, sizeof line,
                  "twin %.2f s, device %.2f s, photon pass %.2f s; the device must find and use the twin's photons "
                  "(same counts, same r²), irradiance within %.0e relative, its nondirect part within %.0e of the "
                  "largest channel (RGBE), no NaN\n",
                  twinSeconds, deviceSeconds, photonSeconds, kEstimateTolerance, kNondirectTolerance);
    out += line;
    out += passed() ? "estimate: passed\n" : "estimate: FAILED\n";
    return out;
}

std::vector<PclEstimateQuery> surfaceEstimateQueries(const Scene& scene, const SceneGeometry& geometry, uint32_t count,
                                                     float maxRadius, uint32_t k, uint64_t seed) {
    std::mt19937_64 rng(seed + 1);
    std::vector<PclEstimateQuery> qs;
    for (const CameraSurfaceHit& h : cameraSurfaceHits(scene, geometry, count, seed))
        qs.push_back(makeQuery(h.p, h.n, randomQueryRadius2(rng, maxRadius), k));
    return qs;
}

void compareEstimates(const std::vector<PclEstimate>& twin, const std::vector<PclEstimate>& device,
                      EstimateCheckRow& row) {
    row.queryCount += twin.size();
    if (twin.size() != device.size()) {
        row.countMismatches += twin.size();
        return;
    }
    for (size_t i = 0; i < twin.size(); ++i) {
        const PclEstimate& t = twin[i];
        const PclEstimate& d = device[i];
        row.used += t.used;
        if (t.r != 0.0f || t.g != 0.0f || t.b != 0.0f) ++row.nonzero;
        if (!finite(t) || !finite(d) || std::isnan(t.radius2) || std::isnan(d.radius2)) {
            ++row.nans;
            continue;
        }
        if (t.used != d.used || t.found != d.found) ++row.countMismatches;
        if (t.radius2 != d.radius2) ++row.radiusMismatches;
        const float tc[3] = {t.r, t.g, t.b}, dc[3] = {d.r, d.g, d.b};
        for (int c = 0; c < 3; ++c) {
            const double scale = std::max(std::fabs(double(tc[c])), std::fabs(double(dc[c])));
            if (scale > 0.0) row.maxRelError = std::max(row.maxRelError, std::fabs(double(tc[c]) - dc[c]) / scale);
        }
        float tn[3], dn[3];
        photon_rgbe_decode(t.nondirect, &tn[0], &tn[1], &tn[2]);
        photon_rgbe_decode(d.nondirect, &dn[0], &dn[1], &dn[2]);
        const double top =
            std::max({double(tn[0]), double(tn[1]), double(tn[2]), double(dn[0]), double(dn[1]), double(dn[2])});
        for (int c = 0; c < 3 && top > 0.0; ++c)
            row.nondirectError = std::max(row.nondirectError, std::fabs(double(tn[c]) - dn[c]) / top);
    }
}

EstimateCheckReport checkEstimate(Device& device, const Scene& scene, const EstimateCheckOptions& options) {
    const PreparedScene prepared = prepareScene(scene);
    return checkEstimate(device, scene, prepared.geometry, prepared.buffers, options);
}

EstimateCheckReport checkEstimate(Device& device, const Scene& scene, const SceneGeometry& geometry,
                                  const SceneBuffers& buffers, const EstimateCheckOptions& options) {
    EstimateCheckReport report;
    const PhotonMaps maps =
        photonMapsOnDevice(device, geometry, buffers, options.photons, options.seed, &report.photonSeconds);
    auto t0 = Clock::now();

    const Bounds3 sb = geometry.bounds();
    const Vec3 ext = sb.extent();
    const float diagonal = std::sqrt(ext.x * ext.x + ext.y * ext.y + ext.z * ext.z);
    const float rMax = std::max(options.radiusFraction * diagonal, 1e-6f);
    const DeviceScene deviceScene(device, geometry, buffers);

    const std::vector<PclEstimateQuery> surface =
        surfaceEstimateQueries(scene, geometry, options.surfaceQueries, rMax, options.k, options.seed * 7 + 1);
    for (const auto& [mapName, map] :
         {std::pair<const char*, const std::vector<PclPhoton>*>{"global", &maps.global}, {"caustic", &maps.caustic}}) {
        float lo[3] = {sb.lo.x, sb.lo.y, sb.lo.z}, hi[3] = {sb.hi.x, sb.hi.y, sb.hi.z};
        for (int a = 0; a < 3; ++a) lo[a] -= rMax, hi[a] += rMax;
        const std::vector<PclEstimateQuery> random =
            randomEstimateQueries(lo, hi, options.randomQueries, rMax, options.k, options.seed * 7 + 2);
        // Each structure built once per map, estimated for every query set, filter and visibility.
        std::vector<PhotonMapOnDevice> built;
        for (KnnStructure s : options.structures) built.emplace_back(device, *map, s, rMax);
        for (const auto& [setName, qs] :
             {std::pair<const char*, const std::vector<PclEstimateQuery>*>{"random", &random}, {"surface", &surface}}) {
            t0 = Clock::now();
            const ReferenceKnn brute = referenceKnnBruteForce(*map, estimateKnnQueries(*qs));
            report.twinSeconds += since(t0);
            const bool surfacePoints = std::string(setName) == "surface";
            for (bool visibility : {false, true}) {
                if (visibility && !(options.visibility && surfacePoints)) continue;
                for (EstimateFilter f : options.filters) {
                    EstimateSettings settings;
                    settings.filter = f;
                    settings.coneK = options.coneK;
                    settings.visibility = visibility;
                    settings.rayEpsilon = buffers.rayEpsilon;
                    t0 = Clock::now();
                    const std::vector<PclEstimate> twin =
                        referenceEstimateWithKnn(*map, *qs, brute, settings, &geometry);
                    report.twinSeconds += since(t0);
                    for (const PhotonMapOnDevice& m : built) {
                        EstimateCheckRow row;
                        row.map = mapName;
                        row.queries = setName;
                        row.structure = knnStructureName(m.structure());
                        row.filter = estimateFilterName(f);
                        row.visibility = visibility;
                        row.photons = map->size();
                        const EstimateResult r = estimateOnDevice(device, m, *qs, settings, &deviceScene);
                        row.deviceSeconds = r.timing.knnSeconds + r.timing.estimateSeconds;
                        report.deviceSeconds += row.deviceSeconds;
                        compareEstimates(twin, r.values, row);
                        report.rows.push_back(row);
                    }
                }
            }
        }
    }
    return report;
}

}  // namespace pcl
