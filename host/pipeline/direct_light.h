// Eye pass stage 3: direct light at the diffuse eye hits (kernels/direct_light.cl;
// kernels/README.md, "Eye pass: direct light"). Point, spot and directional lights: one exact
// shadow ray each. Triangle lights: M samples, each a triangle chosen by scalar power (the area
// light table below) and a point uniform in its area, weighted by the power heuristic against
// the N cosine-sampled gather rays of final_gather, which add an emitter's Le with the
// complementary weight (misWeightBsdf): the two halves together count each area light once.
// With N = 0 (direct visualisation, or no gather) light sampling alone counts, weight 1.
// In a scene with media (params.hasMedia) every shadow ray carries the transmittance of the media
// and invisible boundaries it crosses. Radiance = throughput × ρd/π × Σ. The twin is
// host/reference/direct_light.h.
#pragma once
#include <cstdint>
#include <vector>

#include "device/device.h"
#include "pipeline/device_scene.h"
#include "prep/area_light_table.h"
#include "shared/types.h"

namespace pcl {

// The table on the device, uploaded once.
struct DeviceAreaLights {
    DeviceAreaLights(Device& device, const AreaLightTable& table);
    cl::Buffer cdf, lightOfPrim;
    float total = 0.0f;
    uint32_t areaLights = 0;
};

// Parameters for records [0, sampleCount) of a pass (seed and samples per pixel from the eye
// parameters). lightSamples: M; gatherRays: the N of final_gather (0: light sampling alone);
// hasMedia from the buffers.
PclDirectParams directParams(const PclEyeParams& eye, const SceneGeometry& geometry, const SceneBuffers& buffers,
                             const AreaLightTable& table, uint32_t lightSamples, uint32_t gatherRays);

// Enqueues direct_light over params.sampleCount eye records: hits in, radiance
// (PclRadiance[sampleCount], caller-allocated) out; records without a diffuse hit get 0.
cl::Event directLight(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                      const PclDirectParams& params, const cl::Buffer& hits, cl::Buffer& radiance);

// With the final gather's importance histograms (sampleCount × G² cumulative tables from
// buildGatherHistograms, G = params.histogramCells > 0): the MIS weights use the gather rays'
// real density. The overload above requires params.histogramCells == 0.
cl::Event directLight(Device& device, const DeviceScene& scene, const DeviceAreaLights& lights,
                      const PclDirectParams& params, const cl::Buffer& hits, const cl::Buffer& histograms,
                      cl::Buffer& radiance);

}  // namespace pcl
