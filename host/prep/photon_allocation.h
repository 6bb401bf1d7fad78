// Photon-pass setup shared by the kernels' host side and the CPU twin's checks: how many
// photons each light emits in a pass (kernels/README.md, "Photon allocation"), the pass seed,
// and the PclPhotonParams of one batch.
#pragma once
#include <cstdint>
#include <vector>

#include "geometry/scene_geometry.h"
#include "prep/scene_buffers.h"
#include "shared/types.h"

namespace pcl {

// The scalar power that photon allocation is proportional to: (Φr + Φg + Φb) / 3.
double scalarPower(const PclLight& light);

// Largest-remainder allocation of `photons` in proportion to `weights` (kernels/README.md,
// "Photon allocation"): returns first[], size weights.size() + 1, light i owning photons
// [first[i], first[i+1]). Every positive weight gets at least one photon when photons allow.
std::vector<uint32_t> allocatePhotons(const std::vector<double>& weights, uint32_t photons);

// The seed of progressive pass `pass`: seed + pass * 0x9E3779B97F4A7C15 (64-bit wrap).
uint64_t photonPassSeed(uint64_t seed, uint32_t pass);

// f_i in float (projection_map.h's projectionFraction): projCount / G² as emit_photons computes
// it, times (r / R)² for the sky aimed at its target ball.
float emitFraction(const PclLight& light);

// lightFirstPhoton for `photons` photons of a pass: allocatePhotons over scalar powers s_i
// (global pass) or s_i f_i (caustic pass). Size lights.size() + 1; light i owns
// [first[i], first[i+1]).
std::vector<uint32_t> lightFirstPhoton(const SceneBuffers& buffers, uint32_t photons, uint32_t passKind);

// The flux rgb that the photons of a pass carry in total, computed as emit does it (per photon
// Φ_c / n_i or (Φ_c f_i) / n_i in float, times n_i, summed in double); for a light with an
// emission texture only an estimate (its Φ = π A L̄ holds the estimated mean radiance L̄, while
// each of its photons carries π A L(x) / n_i of its own point: π ∫ L dA in expectation).
void emittedFlux(const SceneBuffers& buffers, const std::vector<uint32_t>& first, uint32_t passKind, double flux[3]);

// The shutter time (normalised, [0, 1)) that emit gives photon `photon` of a pass (u3 of its
// bounce-0 numbers; 0 when the scene does not move): what its records' connections to the camera
// are traced at (connect_caustics).
float photonEmissionTime(const PclPhotonParams& params, uint32_t photon);

// Appends the emission time of every record that deposit wrote for one batch (params'
// firstPhoton onward), from its per-path record counts: deposit keeps path order, so record r
// belongs to the path whose counts it falls in.
void appendRecordTimes(const PclPhotonParams& params, const std::vector<uint32_t>& counts, std::vector<float>& times);

// The params of one batch: photons [firstPhoton, firstPhoton + batchSize) of a pass of kind
// passKind (PCL_PASS_GLOBAL / PCL_PASS_CAUSTIC) with pass seed passSeed.
PclPhotonParams makePhotonParams(const SceneGeometry& geometry, const SceneBuffers& buffers, uint32_t passKind,
                                 uint64_t passSeed, uint32_t maxDepth, uint32_t firstPhoton, uint32_t batchSize,
                                 bool storeGlobal = true);

}  // namespace pcl
