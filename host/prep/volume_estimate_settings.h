// The settings and inputs of the volume radiance estimate (kernels/README.md, "volume_estimate";
// the beam radiance estimate of Jarosz, Zwicker & Jensen 2008), read alike by the kernel's host
// side (pipeline/volume_estimate) and the CPU twin (reference/volume_estimate):
//   volume[i] = Σ_k T_k ⊙ Σ_p K(d_p) Tr(t_p) p_HG(w_p·d) ΔΦ_p   over one volume photon map,
// with a fixed radius r per pass. Here: the settings, the eye segments as the eye pass lays them
// out (slot-major) and their validation, the default radius and its progressive shrinking.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/vec3.h"
#include "shared/types.h"

namespace pcl {

enum class BeamKernel { Box, Biweight };
uint32_t beamKernelCode(BeamKernel k);  // PCL_BEAM_KERNEL_*

struct VolumeEstimateSettings {
    // r > 0: every photon's radius (defaultVolumeRadius, or the pass's shrunk radius), or with
    // per-photon radii the map's reach, the largest of them.
    float radius = 0.0f;
    // Per-photon radii (Jarosz, Zwicker & Jensen 2008): empty, or r_p² of each photon in map
    // order, each in (0, radius²] (volumePhotonRadii2). Empty: every photon's r_p = radius.
    std::vector<float> photonRadius2;
    BeamKernel kernel = BeamKernel::Biweight;  // the paper's choice: smooth at the disc's edge
    // Single scattering (bounce-0 photons) is left to next-event estimation in the eye pass.
    bool skipDirect = false;
    // Photons of L S+ V paths are left to the volume caustic map (set on the global volume map
    // when both maps are estimated: the global pass stores those events too).
    bool skipSpecularPaths = false;
};

// The eye pass's medium segments of one chunk of eye records: segment k of record i at
// segments[k * sampleCount + i] for k < counts[i] ≤ maxSegments (PclVolumeSegment, types.h).
struct VolumeSegments {
    uint32_t sampleCount = 0;
    uint32_t maxSegments = 0;
    std::vector<PclVolumeSegment> segments;  // maxSegments × sampleCount slots
    std::vector<uint32_t> counts;            // sampleCount entries
};

// InternalError naming the field when: counts or segments have the wrong size, a count exceeds
// maxSegments, a used segment has a medium outside [PCL_NO_MEDIUM, mediumCount), a length that is
// negative or not finite, a direction not of unit length (±1e-3), a non-finite start or
// throughput, or a record other than its i.
void validateVolumeSegments(const VolumeSegments& s, size_t mediumCount);
// InternalError unless r is positive and finite, every photon is a volume photon with a finite
// position and photonRadius2 is empty or holds one r_p² in (0, r²] per photon.
void validateVolumeEstimateInput(const std::vector<PclPhoton>& photons, const VolumeEstimateSettings& settings);

// The default radius of a volume map: the median, over up to `samples` of the photons inside
// `region` (evenly spaced in map order), of the distance to their k-th nearest other photon
// (brute force: samples × n distances) — the radius of a ball holding about k photons where the
// photons are. The region is where the eye looks (the scene's bounds): in a global medium most
// photons scatter far outside it, where they are sparse (cornell-fog: a median over every
// photon gave r = 0.66 m, over those in the box 0.047 m); an empty region takes every photon. 0 when
// at most k photons, or none in the region (no radius can be derived: the caller must give one).
float defaultVolumeRadius(const std::vector<PclPhoton>& photons, const Bounds3& region = Bounds3{}, uint32_t k = 32,
                          uint32_t samples = 128);

// Per-photon radii² from each photon's squared distance to its k-th nearest other photon
// (kthDist2[j]; a photon with fewer than k others within reach passes a negative value or
// anything above rMax²): clamped to [rMin², rMax²], then scaled by scale2 (the progressive
// shrinking, 1 at the first pass). InternalError unless 0 < rMin ≤ rMax and scale2 in (0, 1].
std::vector<float> clampVolumePhotonRadii2(const std::vector<float>& kthDist2, float rMin, float rMax, float scale2);

// The smallest float r whose r·r (in float) is ≥ every entry (0 for none): the reach of a map
// with these per-photon radii².
float volumeReach(const std::vector<float>& radius2);

// Progressive shrinking of a 2-D kernel's radius (Knaus & Zwicker 2011, probabilistic progressive
// photon mapping, for a 2-D kernel): r²_{i+1} = r²_i (i + α)/(i + 1), i ≥ 1 the pass whose radius
// r_i was (1-based, as in the paper: r_1 = the default radius), α in (0, 1]. InternalError for
// i = 0 or α outside (0, 1].
float shrinkVolumeRadius2(float radius2, uint32_t pass, float alpha = 2.0f / 3.0f);

}  // namespace pcl
