#include "check/trace.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <thread>

#include "core/clock.h"
#include "core/math.h"
#include "pipeline/intersect.h"
#include "reference/parallel_for.h"
#include "reference/surface.h"

namespace pcl {
namespace {

constexpr double kRelT = 1e-5;
const char* const kSets[3] = {"camera", "inside", "shadow"};

}  // namespace

std::vector<PclRay> checkRays(const Scene& scene, const Bounds3& bounds, size_t n, uint64_t seed,
                              std::vector<std::string>* setOfRay) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Bounds3 b = bounds.empty() ? Bounds3{Vec3(-1.0f), Vec3(1.0f)} : bounds;
    auto inside = [&] { return b.lo + Vec3(u(rng), u(rng), u(rng)) * b.extent(); };
    // Pinhole camera basis (the check wants rays where the camera looks, not lens effects).
    const Camera& cam = scene.camera;
    Vec3 forward = normalize(cam.lookAt - cam.position);
    if (!isFinite(forward)) forward = Vec3(0, 0, -1);  // degenerate camera: any direction will do
    Vec3 right = normalize(cross(forward, cam.up));
    Vec3 up = cross(right, forward);
    if (!isFinite(right) || !isFinite(up)) makeBasis(forward, right, up);
    float tanY = std::tan(0.5f * cam.vfovDegrees * kPi / 180.0f);
    float tanX = tanY * float(cam.width) / float(std::max(cam.height, 1));

    std::vector<PclRay> rays(n);
    if (setOfRay) setOfRay->resize(n);
    for (size_t i = 0; i < n; ++i) {
        int set = int(i % 3);
        PclRay r;
        if (set == 0) {
            float sx = 2 * u(rng) - 1, sy = 2 * u(rng) - 1;
            Vec3 d = normalize(forward + right * (sx * tanX) + up * (sy * tanY));
            r = makeRay(cam.position, d, u(rng));
        } else if (set == 1) {
            float z = 2 * u(rng) - 1, phi = 6.2831853f * u(rng);
            float s = std::sqrt(std::max(0.0f, 1 - z * z));
            r = makeRay(inside(), Vec3(s * std::cos(phi), s * std::sin(phi), z), u(rng), INFINITY, 1e-4f);
        } else {
            Vec3 from = inside(), to = inside();
            r = makeRay(from, to - from, u(rng), 1.0f - 1e-4f, 1e-4f);  // unnormalised direction
        }
        rays[i] = r;
        if (setOfRay) (*setOfRay)[i] = kSets[set];
    }
    return rays;
}

IntersectCheckReport checkIntersect(Device& device, const Scene& scene, size_t n, uint64_t seed) {
    const SceneGeometry g = SceneGeometry::build(scene);
    return checkIntersect(device, scene, g, n, seed);
}

IntersectCheckReport checkIntersect(Device& device, const Scene& scene, const SceneGeometry& g, size_t n,
                                    uint64_t seed) {
    std::vector<std::string> sets;
    std::vector<PclRay> rays = checkRays(scene, g.bounds(), n, seed, &sets);

    IntersectCheckReport report;
    auto start = std::chrono::steady_clock::now();
    std::vector<PclHit> hostClosest(n);
    std::vector<char> hostAny(n);
    parallelForEveryThread(n, [&](size_t i) {
        g.intersect(rays[i], hostClosest[i]);
        hostAny[i] = g.occluded(rays[i]);
    });
    report.hostSeconds = since(start);

    start = std::chrono::steady_clock::now();
    DeviceGeometry dg(device, g);
    cl::Buffer rayBuf = device.upload(rays, CL_MEM_READ_ONLY, "check trace: rays");
    cl::Buffer closestBuf = device.allocate<PclHit>(n, CL_MEM_WRITE_ONLY, "check trace: closest hits");
    cl::Buffer anyBuf = device.allocate<PclHit>(n, CL_MEM_WRITE_ONLY, "check trace: any hits");
    intersectBuffers(device, dg, rayBuf, closestBuf, n, false);
    intersectBuffers(device, dg, rayBuf, anyBuf, n, true);
    std::vector<PclHit> devClosest = device.download<PclHit>(closestBuf, n);
    std::vector<PclHit> devAny = device.download<PclHit>(anyBuf, n);
    report.deviceSeconds = since(start);

    for (const char* name : kSets) report.rows.push_back(IntersectCheck{name});
    for (size_t i = 0; i < n; ++i) {
        IntersectCheck& row = report.rows[i % 3];
        const PclHit& h = hostClosest[i];
        const PclHit& d = devClosest[i];
        row.count++;
        row.hostHits += h.prim != PCL_NO_HIT;
        row.deviceHits += d.prim != PCL_NO_HIT;
        if (h.prim != d.prim) {
            row.primMismatches++;
        } else if (h.prim != PCL_NO_HIT) {
            double rel = std::fabs(double(h.t) - double(d.t)) / std::max(1e-30, std::fabs(double(h.t)));
            row.maxRelT = std::max(row.maxRelT, rel);
            if (rel > kRelT) row.tMismatches++;
        }
        if (bool(hostAny[i]) != (devAny[i].prim != PCL_NO_HIT)) row.anyMismatches++;
    }
    return report;
}

bool IntersectCheckReport::passed() const {
    for (const auto& r : rows)
        if (r.primMismatches || r.tMismatches || r.anyMismatches) return false;
    return true;
}

std::string IntersectCheckReport::table() const {
    std::string out;
    char line[256];
    std::snprintf(line, sizeof line, "%-8s %9s %9s %9s %9s %9s %9s %10s\n", "rays", "count", "host hit", "dev hit",
                  "prim!=", "t!=", "any!=", "max rel t");
    out += line;
    IntersectCheck total{"total"};
    for (const auto& r : rows) {
        std::snprintf(line, sizeof line, "%-8s %9zu %9zu %9zu %9zu %9zu %9zu %10.2e\n", r.rays.c_str(), r.count,
                      r.hostHits, r.deviceHits, r.primMismatches, r.tMismatches, r.anyMismatches, r.maxRelT);
        out += line;
        total.count += r.count;
        total.hostHits += r.hostHits;
        total.deviceHits += r.deviceHits;
        total.primMismatches += r.primMismatches;
        total.tMismatches += r.tMismatches;
        total.anyMismatches += r.anyMismatches;
        total.maxRelT = std::max(total.maxRelT, r.maxRelT);
    }
    std::snprintf(line, sizeof line, "%-8s %9zu %9zu %9zu %9zu %9zu %9zu %10.2e\n", "total", total.count,
                  total.hostHits, total.deviceHits, total.primMismatches, total.tMismatches, total.anyMismatches,
                  total.maxRelT);
    out += line;
    std::snprintf(line, sizeof line, "host traversal %.3f s, device %.3f s (closest + any, incl. upload)\n",
                  hostSeconds, deviceSeconds);
    out += line;
    return out;
}

}  // namespace pcl
