// CPU twin of the volume radiance estimate (kernels/README.md, "volume_estimate"; written from
// the spec, not from volume_estimate.cl): the beam radiance estimate of Jarosz, Zwicker & Jensen
// 2008 along each eye segment,
//   L = Σ_p K(d_p) Tr(t_p) p_HG(w_p·d) ΔΦ_p   over photons within r of the segment, 0 ≤ t_p ≤ ℓ,
// summed per record as Σ_k throughput_k ⊙ L_k. Its own search: photons bucketed by cell (size
// 2r) in a hash map; a segment's candidates are collected cell by cell along it, sorted and made
// unique, so each photon is weighed once, in photon index order, in double.
// Also the point estimate Σ p ΔΦ / (4/3 π r³), the tests' witness.
#pragma once
#include <cstdint>
#include <vector>

#include "core/vec3.h"
#include "prep/volume_estimate_settings.h"
#include "shared/types.h"

namespace pcl {

// The twin of pipeline/volume_estimate's volumeKthNeighbourDist2 (written from the knn spec,
// kernels/README.md): per photon, the (k+1)-th smallest squared distance (float, ((dx² + dy²) +
// dz²)) over every photon of the map, itself included, among those ≤ rMax²; −1 when fewer than
// k + 1. Through a grid of cells ≥ rMax (27 cells per photon). threads: 0 = all cores.
std::vector<float> referenceKthNeighbourDist2(const std::vector<PclPhoton>& photons, uint32_t k, float rMax,
                                              unsigned threads = 0);

// volume[i] for every record of `segments` (validated as the pipeline does). threads 0: all cores.
std::vector<PclRadiance> referenceVolumeEstimate(const std::vector<PclPhoton>& photons,
                                                 const VolumeEstimateSettings& settings, const VolumeSegments& segments,
                                                 const std::vector<PclMedium>& media, unsigned threads = 0);

// L of one segment (throughput not applied) by brute force over every photon: the definition,
// for tests on small maps.
Vec3 referenceBeamEstimateBruteForce(const std::vector<PclPhoton>& photons, const VolumeEstimateSettings& settings,
                                     const PclVolumeSegment& segment, const PclMedium& medium);

// The point estimate at x for light leaving towards the eye along unit towardEye, in a medium
// of asymmetry g: Σ_{|x_p − x| < r} p_HG(−w_p·towardEye) ΔΦ_p / (4/3 π r³) (σs ∫ p L dω, the
// in-scattered radiance per unit length), the same photon selection as the beam estimate.
Vec3 referenceVolumePointEstimate(const std::vector<PclPhoton>& photons, const VolumeEstimateSettings& settings, Vec3 x,
                                  Vec3 towardEye, float g);

// Henyey–Greenstein p(μ) and the beam kernels, as the spec defines them (tests read them).
double referenceBeamPhase(double mu, double g);
double referenceBeamKernel(BeamKernel kernel, double d2, double r2);  // 0 outside the disc

}  // namespace pcl
