// CPU twin of trace_photons (kernels/README.md, "trace_photons"): each photon path bounces
// through the scene with Jensen's Russian roulette, depositing at diffuse hits. Same outputs as
// the kernel: per path S slots of PclPhoton, the deposit count and the end word.
#pragma once
#include <cstdint>
#include <vector>

#include "core/vec3.h"
#include "geometry/scene_geometry.h"
#include "prep/scene_buffers.h"
#include "shared/types.h"

namespace pcl {

struct ReferencePhotonBatch {
    uint32_t slotsPerPath = 0;     // S: maxDepth (either pass: at most one record per hit)
    std::vector<PclPhoton> slots;  // path i owns [i S, i S + S); the first counts[i] are used
    std::vector<uint32_t> counts;  // deposits per path
    std::vector<uint32_t> ends;    // bounce | cause << 8
    // Volume photons (scenes with media; empty otherwise): S slots per path as above, at most
    // one per bounce (a scattering event in a medium).
    std::vector<PclPhoton> volumeSlots;
    std::vector<uint32_t> volumeCounts;
};

// What happened at one hit, for tests (energy along a path).
struct ReferencePhotonHit {
    uint32_t bounce = 0;                // b
    uint32_t event = 0;                 // ReferenceScatter::Kind
    float pDiffuse = 0, pSpecular = 0;  // roulette probabilities before normalisation
    Vec3 powerIn, powerOut;
    uint32_t prim = 0;
    Vec3 position, directionIn, normal, directionOut;  // normal: geometric, as the primitive has it
};

// One roulette-and-scatter step at a hit (step 2 of the spec), exposed for the sampling tests.
struct ReferenceScatter {
    // WrongSide: scattered with a shading normal onto the wrong side of the geometric surface
    // (a reflection through it, a refraction back), which ends the path like GlossyBelow.
    enum Kind : uint32_t { Absorbed, Diffuse, Mirror, Glossy, Reflected, Refracted, GlossyBelow, WrongSide };
    Kind kind = Absorbed;
    Vec3 direction;                     // d'
    Vec3 power;                         // Φ after the step
    float pDiffuse = 0, pSpecular = 0;  // P_d, P_s before normalisation by their sum
};
// d: incoming direction, n: geometric normal (outside for dielectrics), u: the four numbers of
// the bounce (z, Fresnel choice, direction pair).
ReferenceScatter scatterPhotonReference(const PclMaterial& m, Vec3 d, Vec3 n, Vec3 power, const float u[4]);
// The same with shading normal ns (unit, on n's side; kernels/shared/shading_frame.h): the
// scattering frame is ns's; where ns differs from n the direction must leave on the geometric
// side it should (else WrongSide) and the power takes the adjoint factor
// |ω_in·ns| |ω_out·n| / (|ω_in·n| |ω_out·ns|) (host/reference/light_tracer.cpp).
ReferenceScatter scatterPhotonReference(const PclMaterial& m, Vec3 d, Vec3 n, Vec3 ns, Vec3 power, const float u[4]);

// Ward's RGBE and the (θ, φ) bytes, exactly as the spec writes them.
uint32_t referenceEncodeRgbe(Vec3 power);
Vec3 referenceDecodeRgbe(uint32_t rgbe);
uint32_t referenceEncodeDirection(Vec3 w);  // θ | φ << 8
uint32_t referenceEncodeNormal(Vec3 n);     // octahedral u | v << 16, snorm16 each

// Traces path i of the batch (global photon index params.firstPhoton + i) from `ray`; writes
// its slots (S of them) and returns the end word. `hits`, when given, receives every surface hit.
// In a scene with media the path samples free flights (as kernels/trace_photons.cl, media) and
// writes its volume photons to `volumeSlots` (S of them, when given) and their number to
// `volumeCount`.
uint32_t tracePhotonPathReference(const SceneBuffers& buffers, const SceneGeometry& geometry,
                                  const PclPhotonParams& params, const PclPhotonRay& ray, uint32_t i, PclPhoton* slots,
                                  uint32_t& count, std::vector<ReferencePhotonHit>* hits = nullptr,
                                  PclPhoton* volumeSlots = nullptr, uint32_t* volumeCount = nullptr);

ReferencePhotonBatch tracePhotonsReference(const SceneBuffers& buffers, const SceneGeometry& geometry,
                                           const PclPhotonParams& params, const std::vector<PclPhotonRay>& rays,
                                           unsigned threads = 0);

inline uint32_t referenceEndCause(uint32_t end) { return end >> 8; }
inline uint32_t referenceEndBounces(uint32_t end) { return end & 0xFFu; }

}  // namespace pcl
