// Written from kernels/README.md, "volume_estimate" (not from volume_estimate.cl or shared/).
#include "reference/volume_estimate.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include "core/error.h"
#include "core/math.h"
#include "reference/parallel_for.h"

namespace pcl {
namespace {

struct Decoded {
    double x, y, z;
    double w[3];    // unit, towards where the photon came from: the centre of its (θ, φ) byte cell
    double phi[3];  // ΔΦ, from Ward's RGBE
    bool counts;    // passes the selection (skipDirect, skipSpecularPaths)
};

Decoded decode(const PclPhoton& p, const VolumeEstimateSettings& s) {
    Decoded d{};
    d.x = p.x, d.y = p.y, d.z = p.z;
    const double theta = (double(p.packed & 255u) + 0.5) * kPiD / 256.0;
    const int pb = int((p.packed >> 8) & 255u);
    const double ph = (double(pb >= 128 ? pb - 256 : pb) + 0.5) * kPiD / 128.0;
    d.w[0] = std::sin(theta) * std::cos(ph);
    d.w[1] = std::sin(theta) * std::sin(ph);
    d.w[2] = std::cos(theta);
    const uint32_t e = p.rgbe >> 24;
    for (int c = 0; c < 3; ++c) d.phi[c] = e == 0 ? 0.0 : std::ldexp(double((p.rgbe >> (8 * c)) & 255u), int(e) - 136);
    const uint32_t bounce = (p.packed >> PCL_PHOTON_BOUNCE_SHIFT) & 255u;
    const bool specularPath = (p.packed & PCL_PHOTON_AFTER_SPECULAR) && !(p.packed & PCL_PHOTON_AFTER_DIFFUSE);
    d.counts = !(s.skipDirect && bounce == 0) && !(s.skipSpecularPaths && specularPath);
    return d;
}

// Photon j's r_p² (float, as the kernel reads it): its own, or the map's r².
float photonRadius2(const VolumeEstimateSettings& s, size_t j) {
    return s.photonRadius2.empty() ? s.radius * s.radius : s.photonRadius2[j];
}

// One photon's contribution to L of a segment (0 when outside the beam or not selected). The
// selection is the spec's float arithmetic, left to right (as the kernel, FP_CONTRACT off), so a
// photon at d ≈ r is in or out on both sides alike; the weights are in double.
void addBeamContribution(const Decoded& p, float r2, const VolumeEstimateSettings& s, const PclVolumeSegment& seg,
                         const PclMedium& m, double l[3]) {
    if (!p.counts) return;
    const float vx = float(p.x) - seg.ox, vy = float(p.y) - seg.oy, vz = float(p.z) - seg.oz;
    const float t = vx * seg.dx + vy * seg.dy + vz * seg.dz;
    if (!(t >= 0.0f) || !(t <= seg.length)) return;
    const float wx = vx - t * seg.dx, wy = vy - t * seg.dy, wz = vz - t * seg.dz;
    const float d2 = wx * wx + wy * wy + wz * wz;
    if (!(d2 < r2)) return;
    const double k = referenceBeamKernel(s.kernel, d2, r2);
    const double mu = p.w[0] * seg.dx + p.w[1] * seg.dy + p.w[2] * seg.dz;
    const double kp = k * referenceBeamPhase(mu, m.g);
    for (int c = 0; c < 3; ++c) {
        const double sigmaT = double(m.sigmaA[c]) + double(m.sigmaS[c]);
        l[c] += kp * std::exp(-sigmaT * double(t)) * p.phi[c];
    }
}

// Photons bucketed by cell of size 2r (origin 0).
class CellMap {
public:
    CellMap(const std::vector<PclPhoton>& photons, double cell) : cell_(cell) {
        for (uint32_t j = 0; j < photons.size(); ++j)
            cells_[key(coord(photons[j].x), coord(photons[j].y), coord(photons[j].z))].push_back(j);
    }
    int64_t coord(double p) const { return int64_t(std::floor(std::clamp(p / cell_, -1e9, 1e9))); }
    const std::vector<uint32_t>* find(int64_t x, int64_t y, int64_t z) const {
        auto it = cells_.find(key(x, y, z));
        return it == cells_.end() ? nullptr : &it->second;
    }

private:
    static uint64_t key(int64_t x, int64_t y, int64_t z) {
        // 21 bits per axis: cells more than 2²⁰ apart may share a bucket, which only adds
        // candidates (every candidate is tested exactly), never loses one.
        const auto b = [](int64_t v) { return uint64_t(v + (1 << 20)) & 0x1FFFFFu; };
        return b(x) | b(y) << 21 | b(z) << 42;
    }
    double cell_;
    std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

// The photons of cells along the segment within r of it (a superset of those that count).
std::vector<uint32_t> candidates(const CellMap& map, double cell, double r, const PclVolumeSegment& seg) {
    std::vector<uint32_t> out;
    const double len = seg.length;
    const int64_t steps = std::max<int64_t>(1, int64_t(std::ceil(len / cell)));
    for (int64_t s = 0; s < steps; ++s) {
        const double t0 = std::min(len, double(s) * cell), t1 = std::min(len, double(s + 1) * cell);
        const double a[3] = {seg.ox + t0 * seg.dx, seg.oy + t0 * seg.dy, seg.oz + t0 * seg.dz};
        const double b[3] = {seg.ox + t1 * seg.dx, seg.oy + t1 * seg.dy, seg.oz + t1 * seg.dz};
        int64_t lo[3], hi[3];
        for (int c = 0; c < 3; ++c) {
            lo[c] = map.coord(std::min(a[c], b[c]) - r);
            hi[c] = map.coord(std::max(a[c], b[c]) + r);
        }
        for (int64_t z = lo[2]; z <= hi[2]; ++z)
            for (int64_t y = lo[1]; y <= hi[1]; ++y)
                for (int64_t x = lo[0]; x <= hi[0]; ++x)
                    if (const std::vector<uint32_t>* c = map.find(x, y, z)) out.insert(out.end(), c->begin(), c->end());
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

}  // namespace

std::vector<float> referenceKthNeighbourDist2(const std::vector<PclPhoton>& photons, uint32_t k, float rMax,
                                              unsigned threads) {
    if (!(rMax > 0.0f) || !std::isfinite(rMax))
        throw InternalError("volume radii: rMax " + std::to_string(rMax) + ", expected positive and finite");
    std::vector<float> out(photons.size(), -1.0f);
    if (photons.empty()) return out;
    const CellMap map(photons, double(rMax));
    const float r2max = rMax * rMax;
    referenceParallelFor(photons.size(), threads, [&](size_t q) {
        const PclPhoton& a = photons[q];
        const int64_t cx = map.coord(a.x), cy = map.coord(a.y), cz = map.coord(a.z);
        std::vector<float> d2;
        for (int64_t z = cz - 1; z <= cz + 1; ++z)
            for (int64_t y = cy - 1; y <= cy + 1; ++y)
                for (int64_t x = cx - 1; x <= cx + 1; ++x)
                    if (const std::vector<uint32_t>* c = map.find(x, y, z))
                        for (uint32_t j : *c) {
                            const PclPhoton& p = photons[j];
                            // Each photon once: only through the cell that is its own (hash clashes).
                            if (map.coord(p.x) != x || map.coord(p.y) != y || map.coord(p.z) != z) continue;
                            const float dx = p.x - a.x, dy = p.y - a.y, dz = p.z - a.z;
                            const float e = (dx * dx + dy * dy) + dz * dz;
                            if (e <= r2max) d2.push_back(e);
                        }
        if (d2.size() < size_t(k) + 1) return;
        std::nth_element(d2.begin(), d2.begin() + k, d2.end());
        out[q] = d2[k];
    });
    return out;
}

double referenceBeamPhase(double mu, double g) {
    const double den = 1.0 + g * g - 2.0 * g * mu;
    return (1.0 - g * g) / (4.0 * kPiD * std::pow(den, 1.5));
}

double referenceBeamKernel(BeamKernel kernel, double d2, double r2) {
    if (!(d2 < r2)) return 0.0;
    if (kernel == BeamKernel::Box) return 1.0 / (kPiD * r2);
    const double u = 1.0 - d2 / r2;
    return 3.0 / (kPiD * r2) * u * u;
}

std::vector<PclRadiance> referenceVolumeEstimate(const std::vector<PclPhoton>& photons,
                                                 const VolumeEstimateSettings& settings, const VolumeSegments& segments,
                                                 const std::vector<PclMedium>& media, unsigned threads) {
    validateVolumeSegments(segments, media.size());
    validateVolumeEstimateInput(photons, settings);
    std::vector<Decoded> decoded(photons.size());
    for (size_t j = 0; j < photons.size(); ++j) decoded[j] = decode(photons[j], settings);
    const double r = settings.radius, cell = 2.0 * r;
    const CellMap map(photons, cell);
    std::vector<PclRadiance> out(segments.sampleCount, PclRadiance{0, 0, 0, 0});
    referenceParallelFor(segments.sampleCount, threads, [&](size_t i) {
        double sum[3] = {0, 0, 0};
        for (uint32_t k = 0; k < segments.counts[i]; ++k) {
            const PclVolumeSegment& seg = segments.segments[size_t(k) * segments.sampleCount + i];
            if (seg.medium == PCL_NO_MEDIUM || !(seg.length > 0.0f)) continue;
            const PclMedium& m = media[size_t(seg.medium)];
            double l[3] = {0, 0, 0};
            for (uint32_t j : candidates(map, cell, r, seg))
                addBeamContribution(decoded[j], photonRadius2(settings, j), settings, seg, m, l);
            for (int c = 0; c < 3; ++c) sum[c] += double(seg.throughput[c]) * l[c];
        }
        out[i] = PclRadiance{float(sum[0]), float(sum[1]), float(sum[2]), 0.0f};
    });
    return out;
}

Vec3 referenceBeamEstimateBruteForce(const std::vector<PclPhoton>& photons, const VolumeEstimateSettings& settings,
                                     const PclVolumeSegment& segment, const PclMedium& medium) {
    validateVolumeEstimateInput(photons, settings);
    double l[3] = {0, 0, 0};
    if (segment.length > 0.0f)
        for (size_t j = 0; j < photons.size(); ++j)
            addBeamContribution(decode(photons[j], settings), photonRadius2(settings, j), settings, segment, medium, l);
    return {float(l[0]), float(l[1]), float(l[2])};
}

Vec3 referenceVolumePointEstimate(const std::vector<PclPhoton>& photons, const VolumeEstimateSettings& settings, Vec3 x,
                                  Vec3 towardEye, float g) {
    validateVolumeEstimateInput(photons, settings);
    const double r = settings.radius;
    double l[3] = {0, 0, 0};
    for (const PclPhoton& ph : photons) {
        const Decoded p = decode(ph, settings);
        if (!p.counts) continue;
        const double dx = p.x - x.x, dy = p.y - x.y, dz = p.z - x.z;
        if (!(dx * dx + dy * dy + dz * dz < r * r)) continue;
        // The photon travels along −w; the light leaves towards the eye: μ = (−w)·towardEye.
        const double mu = -(p.w[0] * towardEye.x + p.w[1] * towardEye.y + p.w[2] * towardEye.z);
        const double phase = referenceBeamPhase(mu, g);
        for (int c = 0; c < 3; ++c) l[c] += phase * p.phi[c];
    }
    const double volume = 4.0 / 3.0 * kPiD * r * r * r;
    return {float(l[0] / volume), float(l[1] / volume), float(l[2] / volume)};
}

}  // namespace pcl
