// What the photon-pass checks (emit.cpp, trace_photons.cpp, deposit.cpp, pass.cpp) share: the
// tolerances, the two passes of a check with their photons split over two batches, and how two
// photon records are compared. Used by those files only.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "check/photon_stages.h"
#include "core/vec3.h"
#include "prep/scene_buffers.h"
#include "reference/emit.h"
#include "reference/photon_pass.h"
#include "reference/trace_photons.h"
#include "shared/types.h"

namespace pcl::photon_check {

inline constexpr double kPositionTolerance = 1e-4;   // of max(|p|∞, scene radius)
inline constexpr double kDirectionTolerance = 1e-4;  // absolute, per component of a unit vector
inline constexpr double kPowerTolerance = 1e-5;      // of the largest channel

// One pass of the check: its allocation and its photons split over two batches.
struct CheckPass {
    const char* name;
    std::vector<uint32_t> first;
    std::vector<PclPhotonParams> batches;
};

inline std::vector<CheckPass> checkPasses(const SceneGeometry& geometry, const SceneBuffers& buffers,
                                          const PhotonCheckOptions& o) {
    std::vector<CheckPass> passes;
    const uint64_t seed = referencePhotonPassSeed(o.seed, 0);
    for (uint32_t pass : {PCL_PASS_GLOBAL, PCL_PASS_CAUSTIC}) {
        CheckPass p{
            pass == PCL_PASS_GLOBAL ? "global" : "caustic", referenceLightFirstPhoton(buffers, pass, o.photons), {}};
        const uint32_t total = p.first.back();
        const uint32_t half = total / 2;
        for (auto [start, n] : {std::pair<uint32_t, uint32_t>{0, half}, {half, total - half}})
            if (n > 0) p.batches.push_back(referencePhotonParams(buffers, geometry, seed, pass, start, n, o.maxDepth));
        passes.push_back(std::move(p));
    }
    return passes;
}

// The report of `stage` with one row per pass of checkPasses: fill(pass, row, report) compares
// the pass's batches into its row (and adds its seconds to the report).
template <class Fill>
PhotonCheckReport perPassReport(const char* stage, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                const PhotonCheckOptions& options, Fill&& fill) {
    PhotonCheckReport report;
    report.stage = stage;
    report.maxDivergentFraction = options.maxDivergentFraction;
    for (const CheckPass& pass : checkPasses(geometry, buffers, options)) {
        PhotonCheckRow row;
        row.pass = pass.name;
        fill(pass, row, report);
        report.rows.push_back(row);
    }
    return report;
}

inline Vec3 originOf(const PclPhotonRay& r) { return {r.ox, r.oy, r.oz}; }
inline Vec3 directionOf(const PclPhotonRay& r) { return {r.dx, r.dy, r.dz}; }
inline float maxAbs(Vec3 v) { return std::max(std::fabs(v.x), std::max(std::fabs(v.y), std::fabs(v.z))); }

inline double positionError(Vec3 a, Vec3 b, float sceneRadius) {
    return maxAbs(a - b) / std::max(std::max(maxAbs(a), sceneRadius), 1e-30f);
}

// Decoded channels within one mantissa step of the larger exponent byte.
inline bool rgbeClose(uint32_t a, uint32_t b) {
    if (a == b) return true;
    const int E = int(std::max(a >> 24, b >> 24));
    const double step = std::ldexp(1.0, E - 136);
    const Vec3 da = referenceDecodeRgbe(a), db = referenceDecodeRgbe(b);
    return maxAbs(da - db) <= step * (1.0 + 1e-6);
}

inline bool recordsAgree(const PclPhoton& a, const PclPhoton& b, float radius) {
    return positionError({a.x, a.y, a.z}, {b.x, b.y, b.z}, radius) <= kPositionTolerance && a.packed == b.packed &&
           rgbeClose(a.rgbe, b.rgbe);
}

}  // namespace pcl::photon_check
