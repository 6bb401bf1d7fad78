// CPU twin of the emit stage (kernels/README.md, "emit"): one PclPhotonRay per photon of a
// batch, from the same Philox counters as kernels/emit.cl, written from the spec with the host
// warps (reference/sampling.h) and no code shared with the kernel.
#pragma once
#include <cstdint>
#include <vector>

#include "prep/scene_buffers.h"
#include "shared/types.h"

namespace pcl {

// The pass seed: seed + pass * 0x9E3779B97F4A7C15 (64-bit wrap).
uint64_t referencePhotonPassSeed(uint64_t seed, uint32_t pass);
inline uint64_t referenceParamsSeed(const PclPhotonParams& p) {
    return uint64_t(p.seedLo) | (uint64_t(p.seedHi) << 32);
}

// The light owning global photon index j: first[i] <= j < first[i+1].
uint32_t referenceLightOfPhoton(const std::vector<uint32_t>& lightFirstPhoton, uint32_t j);

// Photon weights for allocation: scalar power s_i (global pass) or s_i f_i (caustic pass),
// f_i = projCount_i / PCL_PROJ_GRID^2.
std::vector<double> referenceAllocationWeights(const SceneBuffers& buffers, uint32_t pass);

// Photon j (global index) of the pass described by params.
PclPhotonRay emitPhotonReference(const SceneBuffers& buffers, const std::vector<uint32_t>& lightFirstPhoton,
                                 const PclPhotonParams& params, uint32_t j);

// The whole batch: element i is photon params.firstPhoton + i. threads 0: all cores.
std::vector<PclPhotonRay> emitPhotonsReference(const SceneBuffers& buffers,
                                               const std::vector<uint32_t>& lightFirstPhoton,
                                               const PclPhotonParams& params, unsigned threads = 0);

// The spot light's cosθ for a uniform s1 (kernels/README.md, "Spot cosθ"), solved in double.
float referenceSpotCosTheta(float s1, float cosInner, float cosOuter);

}  // namespace pcl
