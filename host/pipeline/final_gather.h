// Eye pass stage 4: final gathering (kernels/final_gather.cl; kernels/README.md, "Eye pass:
// final gather"). At each diffuse eye hit N gather rays, cosine-distributed about the normal
// (the diffuse BRDF's importance sampling), are traced; a gather ray follows specular surfaces
// for up to maxSpecular bounces (lobe choice as in eye_paths) and at the first hit whose diffuse
// part is chosen leaves an irradiance query there — the global map is read only at gather hits,
// never at the eye hit (the notes' rule); emitters met on the way add Le × the chain throughput
// × the MIS weight of direct_light (misWeightBsdf for triangle lights, 1 for others).
// Then the IrradianceSource answers the queries, and a resolve kernel sums per eye record:
//   L = throughput × ρd × (1/N) Σ_g [weight_g · E_g + emitted_g]
// (f cosθ / pdf = ρd for cosine sampling). The twin is host/reference/final_gather.h.
//
//   PclGatherParams gp = gatherParams(directParams, 32, 50, rMax², 2);
//   cl::Buffer queries = device.allocate<PclEstimateQuery>(n * N), gathered = ...<PclGatherHit>(n * N);
//   traceGatherRays(device, scene, lights, gp, eyeHits, queries, gathered);
//   cl::Buffer E = source.evaluate(device, queries, n * N);
//   resolveGather(device, gp, eyeHits, gathered, E, radiance);
// or finalGather(...) for all three.
#pragma once
#include <cstdint>
#include <vector>

#include "device/device.h"
#include "pipeline/device_scene.h"
#include "pipeline/direct_light.h"
#include "pipeline/irradiance_source.h"
#include "shared/types.h"

namespace pcl {

constexpr uint32_t kDefaultGatherSpecular = 4;

// From the direct-light parameters (seed, M, table total, scene counts); gatherRays ≥ 1 must
// equal direct.gatherRays for the MIS weights to add up (InternalError otherwise).
PclGatherParams gatherParams(const PclDirectParams& direct, uint32_t gatherRays, uint32_t k, float maxRadius2,
                             uint32_t maxSpecular = kDefaultGatherSpecular);

// Enqueues final_gather_trace over params.sampleCount × params.gatherRays rays (ray g of record
// i at i·N + g): hits in; queries (PclEstimateQuery) and gathered (PclGatherHit), each
// sampleCount × N, caller-allocated, out. A ray with no diffuse hit gets a query with
// maxRadius2 = 0 at the origin and weight 0.
cl::Event traceGatherRays(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                          const PclGatherParams& params, const cl::Buffer& hits, cl::Buffer& queries,
                          cl::Buffer& gathered);

// Optional importance sampling of the gather rays (Jensen 1995; kernels/README.md, "final
// gather"): per diffuse eye record a G × G histogram (G = params.histogramCells, 1..16) of the
// incident flux of the params.k global photons nearest the hit (within params.maxRadius2) over
// the cosine map's square, mixed with the cosine density (PCL_GATHER_UNIFORM_MIX), as cumulative
// tables: sampleCount × G² floats, returned. Direct light must be given the same tables and
// the same G (PclDirectParams::histogramCells) for its MIS weights.
cl::Buffer buildGatherHistograms(Device& device, const PhotonMapOnDevice& global, const PclGatherParams& params,
                                 const cl::Buffer& hits);
// traceGatherRays with the tables (params.histogramCells > 0); the overload above requires
// params.histogramCells == 0.
cl::Event traceGatherRays(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                          const PclGatherParams& params, const cl::Buffer& hits, const cl::Buffer& histograms,
                          cl::Buffer& queries, cl::Buffer& gathered);

// Enqueues final_gather_resolve: radiance[i] (PclRadiance, caller-allocated) from the records,
// the gathered rays and the irradiance records (params.irradianceStride floats each).
cl::Event resolveGather(Device& device, const PclGatherParams& params, const cl::Buffer& hits,
                        const cl::Buffer& gathered, const cl::Buffer& irradiance, cl::Buffer& radiance);

struct GatherTiming {
    double traceSeconds = 0.0, irradianceSeconds = 0.0, resolveSeconds = 0.0;  // device time
};

// All three on buffers; params.irradianceStride is taken from the source. Scratch buffers are
// allocated per call (sampleCount × N × 64 bytes).
GatherTiming finalGather(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                         PclGatherParams params, const cl::Buffer& hits, IrradianceSource& source,
                         cl::Buffer& radiance);
// The same with importance histograms (buildGatherHistograms) when params.histogramCells > 0.
GatherTiming finalGather(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                         PclGatherParams params, const cl::Buffer& hits, const cl::Buffer& histograms,
                         IrradianceSource& source, cl::Buffer& radiance);

}  // namespace pcl
