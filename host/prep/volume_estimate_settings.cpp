#include "prep/volume_estimate_settings.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace pcl {

uint32_t beamKernelCode(BeamKernel k) { return k == BeamKernel::Box ? PCL_BEAM_KERNEL_BOX : PCL_BEAM_KERNEL_BIWEIGHT; }

void validateVolumeSegments(const VolumeSegments& s, size_t mediumCount) {
    const auto fail = [](const std::string& what) { throw InternalError("volume estimate: segments: " + what); };
    if (s.counts.size() != s.sampleCount)
        fail("counts has " + std::to_string(s.counts.size()) + " entries, expected sampleCount " +
             std::to_string(s.sampleCount));
    if (s.segments.size() != size_t(s.maxSegments) * s.sampleCount)
        fail("segments has " + std::to_string(s.segments.size()) +
             " slots, expected maxSegments × sampleCount = " + std::to_string(size_t(s.maxSegments) * s.sampleCount));
    for (uint32_t i = 0; i < s.sampleCount; ++i) {
        if (s.counts[i] > s.maxSegments)
            fail("counts[" + std::to_string(i) + "] = " + std::to_string(s.counts[i]) + ", expected ≤ maxSegments " +
                 std::to_string(s.maxSegments));
        for (uint32_t k = 0; k < s.counts[i]; ++k) {
            const PclVolumeSegment& g = s.segments[size_t(k) * s.sampleCount + i];
            const std::string at = "segment " + std::to_string(k) + " of record " + std::to_string(i) + ": ";
            if (g.medium < PCL_NO_MEDIUM || g.medium >= int64_t(mediumCount))
                fail(at + "medium " + std::to_string(g.medium) + ", expected -1 (vacuum) or an index below " +
                     std::to_string(mediumCount));
            if (!(g.length >= 0.0f) || !std::isfinite(g.length))
                fail(at + "length " + std::to_string(g.length) + ", expected finite and ≥ 0");
            const float len = std::sqrt(g.dx * g.dx + g.dy * g.dy + g.dz * g.dz);
            if (!(std::fabs(len - 1.0f) <= 1e-3f)) fail(at + "|direction| " + std::to_string(len) + ", expected 1");
            if (!std::isfinite(g.ox) || !std::isfinite(g.oy) || !std::isfinite(g.oz)) fail(at + "start not finite");
            for (int c = 0; c < 3; ++c)
                if (!std::isfinite(g.throughput[c])) fail(at + "throughput not finite");
            if (g.record != i) fail(at + "record " + std::to_string(g.record) + ", expected " + std::to_string(i));
        }
    }
}

void validateVolumeEstimateInput(const std::vector<PclPhoton>& photons, const VolumeEstimateSettings& settings) {
    if (!(settings.radius > 0.0f) || !std::isfinite(settings.radius))
        throw InternalError("volume estimate: radius " + std::to_string(settings.radius) +
                            ", expected positive and finite");
    if (!settings.photonRadius2.empty() && settings.photonRadius2.size() != photons.size())
        throw InternalError("volume estimate: photonRadius2 has " + std::to_string(settings.photonRadius2.size()) +
                            " entries, expected one per photon (" + std::to_string(photons.size()) + ")");
    const float reach2 = settings.radius * settings.radius;
    for (size_t j = 0; j < settings.photonRadius2.size(); ++j) {
        const float r2 = settings.photonRadius2[j];
        if (!(r2 > 0.0f && r2 <= reach2))
            throw InternalError("volume estimate: photon " + std::to_string(j) + " has r² " + std::to_string(r2) +
                                ", expected in (0, radius² = " + std::to_string(reach2) + "]");
    }
    for (size_t j = 0; j < photons.size(); ++j) {
        const PclPhoton& p = photons[j];
        if ((p.packed & PCL_PHOTON_VOLUME) == 0u)
            throw InternalError("volume estimate: photon " + std::to_string(j) +
                                " is not a volume photon (flag PCL_PHOTON_VOLUME clear)");
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw InternalError("volume estimate: photon " + std::to_string(j) + " has a non-finite position");
    }
}

float defaultVolumeRadius(const std::vector<PclPhoton>& photons, const Bounds3& region, uint32_t k, uint32_t samples) {
    const size_t n = photons.size();
    if (k == 0 || samples == 0 || n <= k) return 0.0f;
    std::vector<size_t> inside;
    for (size_t j = 0; j < n; ++j) {
        const PclPhoton& p = photons[j];
        if (region.empty() || (p.x >= region.lo.x && p.x <= region.hi.x && p.y >= region.lo.y && p.y <= region.hi.y &&
                               p.z >= region.lo.z && p.z <= region.hi.z))
            inside.push_back(j);
    }
    if (inside.empty()) return 0.0f;
    const size_t m = std::min<size_t>(samples, inside.size());
    std::vector<float> kth(m);
    std::vector<float> d2;
    d2.reserve(n);
    for (size_t s = 0; s < m; ++s) {
        const size_t q = inside[s * inside.size() / m];
        const PclPhoton& a = photons[q];
        d2.clear();
        for (size_t j = 0; j < n; ++j) {
            if (j == q) continue;
            const float dx = photons[j].x - a.x, dy = photons[j].y - a.y, dz = photons[j].z - a.z;
            d2.push_back(dx * dx + dy * dy + dz * dz);
        }
        std::nth_element(d2.begin(), d2.begin() + (k - 1), d2.end());
        kth[s] = d2[k - 1];
    }
    std::nth_element(kth.begin(), kth.begin() + m / 2, kth.end());
    return std::sqrt(kth[m / 2]);
}

std::vector<float> clampVolumePhotonRadii2(const std::vector<float>& kthDist2, float rMin, float rMax, float scale2) {
    if (!(rMin > 0.0f && rMin <= rMax) || !std::isfinite(rMax))
        throw InternalError("volume estimate: per-photon radii clamped to [" + std::to_string(rMin) + ", " +
                            std::to_string(rMax) + "], expected 0 < rMin ≤ rMax finite");
    if (!(scale2 > 0.0f && scale2 <= 1.0f))
        throw InternalError("volume estimate: radius scale² " + std::to_string(scale2) + ", expected in (0, 1]");
    const float lo = rMin * rMin, hi = rMax * rMax;
    std::vector<float> out(kthDist2.size());
    for (size_t j = 0; j < kthDist2.size(); ++j) {
        const float d2 = kthDist2[j];
        // NaN, negative (not found) or beyond reach: the largest radius.
        const float c = (d2 >= 0.0f && d2 <= hi) ? std::max(d2, lo) : hi;
        out[j] = c * scale2;
    }
    return out;
}

float volumeReach(const std::vector<float>& radius2) {
    float m = 0.0f;
    for (float r2 : radius2) m = std::max(m, r2);
    float r = std::sqrt(m);
    while (r * r < m) r = std::nextafter(r, INFINITY);
    return r;
}

float shrinkVolumeRadius2(float radius2, uint32_t pass, float alpha) {
    if (pass == 0) throw InternalError("volume estimate: shrinking after pass 0; passes count from 1");
    if (!(alpha > 0.0f && alpha <= 1.0f))
        throw InternalError("volume estimate: α " + std::to_string(alpha) + ", expected in (0, 1]");
    return radius2 * (float(pass) + alpha) / (float(pass) + 1.0f);
}

}  // namespace pcl
