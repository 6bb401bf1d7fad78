#include "check/volume_estimate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "check/on_device.h"
#include "core/clock.h"
#include "pipeline/photon_pass.h"
#include "pipeline/volume_estimate.h"
#include "prep/medium_boundaries.h"
#include "reference/camera.h"
#include "reference/medium.h"
#include "reference/surface.h"
#include "reference/volume_estimate.h"

namespace pcl {

bool VolumeEstimateCheckRow::passed() const {
    return records > 0 && nans == 0 && nonzero > 0 && fraction() >= kVolumeRequiredFraction && radiusMismatches == 0;
}

bool VolumeEstimateCheckReport::passed() const {
    return failure.empty() && !rows.empty() &&
           std::all_of(rows.begin(), rows.end(), [](const auto& r) { return r.passed(); });
}

std::string VolumeEstimateCheckReport::table() const {
    std::string out;
    char line[512];
    if (!failure.empty()) return "volume estimate: " + failure + "\nvolume_estimate: FAILED\n";
    std::snprintf(line, sizeof line, "%-14s %-8s %-6s %6s %6s %8s %8s %7s %9s %7s %8s %4s %10s %9s %8s\n", "map",
                  "kernel", "radii", "direct", "LS+V", "photons", "radius", "records", "segments", "nonzero", "matched",
                  "nan", "max rel", "device s", "twin s");
    out += line;
    for (const auto& r : rows) {
        std::snprintf(line, sizeof line,
                      "%-14s %-8s %-6s %6s %6s %8zu %8.5f %7zu %9zu %7zu %7.3f%% %4zu %10.2e %9.4f %8.3f%s\n",
                      r.map.c_str(), r.kernel.c_str(), r.photonRadii ? "photon" : "fixed",
                      r.skipDirect ? "skip" : "keep", r.skipSpecularPaths ? "skip" : "keep", r.photons, r.radius,
                      r.records, r.segments, r.nonzero, 100.0 * r.fraction(), r.nans, r.maxRelError, r.deviceSeconds,
                      r.twinSeconds, r.passed() ? "" : (r.radiusMismatches ? "  FAIL (radii differ)" : "  FAIL"));
        out += line;
    }
    std::snprintf(line, sizeof line,
                  "photon pass %.2f s; a record matches when every channel is within %.0e relative; a row needs "
                  "%.1f %% matched, no NaN/Inf, some nonzero radiance\n",
                  photonSeconds, kVolumeTolerance, 100.0 * kVolumeRequiredFraction);
    out += line;
    out += passed() ? "volume_estimate: passed\n" : "volume_estimate: FAILED\n";
    return out;
}

VolumeSegments cameraVolumeSegments(const Scene& scene, const SceneGeometry& geometry, uint32_t records,
                                    uint32_t maxSegments, uint64_t seed) {
    const MediumBoundaries boundaries = findMediumBoundaries(scene, geometry);
    RayCamera camera(scene.camera);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    VolumeSegments out;
    out.sampleCount = records;
    out.maxSegments = maxSegments;
    out.segments.assign(size_t(records) * maxSegments, PclVolumeSegment{});
    out.counts.assign(records, 0u);
    const int w = std::max(scene.camera.width, 1), h = std::max(scene.camera.height, 1);
    for (uint32_t i = 0; i < records; ++i) {
        const int x = std::min(int(u(rng) * w), w - 1), y = std::min(int(u(rng) * h), h - 1);
        CameraSample s;
        s.filmX = u(rng), s.filmY = u(rng), s.lensU = u(rng), s.lensV = u(rng), s.time = u(rng);
        const PclRay first = camera.generateRay(x, y, s);
        const Vec3 d = normalize(rayDirection(first));
        PclRay ray = makeRay(rayOrigin(first), d, first.time);
        int32_t medium = boundaries.cameraMedium;
        Vec3 throughput(1.0f);
        std::vector<PclVolumeSegment> found;
        for (uint32_t k = 0; k < maxSegments; ++k) {
            PclHit hit;
            if (!geometry.intersect(ray, hit)) {
                found.clear();  // left the scene: no finite segment to give
                break;
            }
            const SurfacePoint sp = surfaceAt(scene, geometry, ray, hit);
            if (medium != PCL_NO_MEDIUM) {
                PclVolumeSegment g{};
                g.ox = ray.ox, g.oy = ray.oy, g.oz = ray.oz;
                g.dx = d.x, g.dy = d.y, g.dz = d.z;
                g.length = hit.t;
                g.time = ray.time;
                g.throughput[0] = throughput.x, g.throughput[1] = throughput.y, g.throughput[2] = throughput.z;
                g.medium = medium;
                g.record = i;
                found.push_back(g);
                throughput = throughput * transmittance(scene.media[size_t(medium)].sigmaT(), hit.t);
            }
            if (!(sp.material && sp.material->interface)) break;
            medium = boundaries.beyond(sp.prim, dot(d, sp.ng));
            ray = spawnRay(sp.p, sp.ng, d, ray.time, std::numeric_limits<float>::infinity());
        }
        out.counts[i] = uint32_t(found.size());
        for (size_t k = 0; k < found.size(); ++k) out.segments[k * records + i] = found[k];
    }
    return out;
}

namespace {

bool finiteRadiance(const PclRadiance& r) { return std::isfinite(r.r) && std::isfinite(r.g) && std::isfinite(r.b); }

void compare(const std::vector<PclRadiance>& device, const std::vector<PclRadiance>& twin,
             VolumeEstimateCheckRow& row) {
    row.records = twin.size();
    if (device.size() != twin.size()) return;  // nothing matched
    for (size_t i = 0; i < twin.size(); ++i) {
        const PclRadiance& d = device[i];
        const PclRadiance& t = twin[i];
        if (!finiteRadiance(d) || !finiteRadiance(t)) {
            ++row.nans;
            continue;
        }
        if (t.r != 0.0f || t.g != 0.0f || t.b != 0.0f) ++row.nonzero;
        double worst = 0.0;
        const float dv[3] = {d.r, d.g, d.b}, tv[3] = {t.r, t.g, t.b};
        for (int c = 0; c < 3; ++c) {
            const double m = std::max(std::fabs(double(dv[c])), std::fabs(double(tv[c])));
            if (m > 0.0) worst = std::max(worst, std::fabs(double(dv[c]) - double(tv[c])) / m);
        }
        row.maxRelError = std::max(row.maxRelError, worst);
        if (worst <= kVolumeTolerance) ++row.matched;
    }
}

}  // namespace

VolumeEstimateCheckReport checkVolumeEstimate(Device& device, const Scene& scene, const SceneGeometry& geometry,
                                              const SceneBuffers& buffers, const VolumeEstimateCheckOptions& options) {
    VolumeEstimateCheckReport report;
    if (!scene.hasMedia()) {
        report.failure = "the scene has no participating medium (nothing to estimate)";
        return report;
    }
    const PhotonMaps maps =
        photonMapsOnDevice(device, geometry, buffers, options.photons, options.seed, &report.photonSeconds);
    auto t0 = Clock::now();
    const VolumeSegments segments =
        cameraVolumeSegments(scene, geometry, options.records, options.maxSegments, options.seed + 1);
    size_t segmentCount = 0;
    for (uint32_t c : segments.counts) segmentCount += c;

    struct MapCase {
        const char* name;
        const std::vector<PclPhoton>* photons;
    };
    for (const MapCase& m : {MapCase{"global volume", &maps.volume}, MapCase{"volume caustic", &maps.volumeCaustic}}) {
        const float radius = defaultVolumeRadius(*m.photons, geometry.bounds(), options.radiusK);
        if (!(radius > 0.0f)) continue;  // too few photons (in the scene's bounds) for a radius
        const bool global = m.photons == &maps.volume;
        for (int photonRadii = 0; photonRadii < 2; ++photonRadii) {
            VolumeEstimateCheckRow radii;
            VolumeEstimateSettings base;
            base.radius = radius;
            if (photonRadii) {
                const std::vector<float> d = volumeKthNeighbourDist2(device, *m.photons, options.radiusK, 2 * radius);
                const std::vector<float> t = referenceKthNeighbourDist2(*m.photons, options.radiusK, 2 * radius);
                for (size_t j = 0; j < d.size(); ++j) radii.radiusMismatches += d[j] != t[j];
                base.photonRadius2 = clampVolumePhotonRadii2(t, 0.25f * radius, 2.0f * radius, 1.0f);
                base.radius = volumeReach(base.photonRadius2);
            }
            for (BeamKernel kernel : {BeamKernel::Box, BeamKernel::Biweight})
                for (int skip = 0; skip < (global ? 2 : 1); ++skip) {
                    if (photonRadii && (kernel == BeamKernel::Box || skip)) continue;  // one row: the renderer's
                    VolumeEstimateSettings s = base;
                    s.kernel = kernel;
                    s.skipDirect = skip != 0;
                    s.skipSpecularPaths = skip != 0;
                    VolumeEstimateCheckRow row = radii;
                    row.photonRadii = photonRadii != 0;
                    row.map = m.name;
                    row.kernel = kernel == BeamKernel::Box ? "box" : "biweight";
                    row.skipDirect = s.skipDirect;
                    row.skipSpecularPaths = s.skipSpecularPaths;
                    row.photons = m.photons->size();
                    row.segments = segmentCount;
                    row.radius = s.radius;
                    const std::vector<PclRadiance> d =
                        volumeEstimateOnDevice(device, *m.photons, s, segments, buffers.media, &row.deviceSeconds);
                    t0 = Clock::now();
                    const std::vector<PclRadiance> t = referenceVolumeEstimate(*m.photons, s, segments, buffers.media);
                    row.twinSeconds = since(t0);
                    compare(d, t, row);
                    report.rows.push_back(row);
                }
        }
    }
    if (report.rows.empty())
        report.failure = "no volume map holds more than " + std::to_string(options.radiusK) +
                         " photons, or any in the scene's bounds (global " + std::to_string(maps.volume.size()) +
                         ", caustic " + std::to_string(maps.volumeCaustic.size()) + ")";
    return report;
}

}  // namespace pcl
