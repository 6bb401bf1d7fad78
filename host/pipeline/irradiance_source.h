// "A function of (points, normals) → irradiance on the device": what final gathering (and the
// estimates at the eye hits) read the photon maps through. Either the full k-nearest-neighbour
// estimate (pipeline/estimate.h) or Christensen's precomputed irradiance lookup
// (pipeline/precomputed_irradiance.h) plugs in; a test may plug in anything else.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "device/device.h"
#include "pipeline/device_scene.h"
#include "pipeline/estimate.h"
#include "pipeline/precomputed_irradiance.h"
#include "shared/types.h"

namespace pcl {

struct IrradianceSource {
    std::string name;           // "estimate (kd-tree, cone, k = 50)", "precomputed irradiance", ...
    uint32_t strideFloats = 8;  // floats per result record; its first three are E rgb (W/m²)
    // E at `count` PclEstimateQuery in `queries` (position, maxRadius2, unit normal on the lit
    // side, k): returns a device buffer of count × strideFloats floats. A query with
    // maxRadius2 = 0 must give 0. Enqueues and waits.
    std::function<cl::Buffer(Device& device, const cl::Buffer& queries, size_t count)> evaluate;
    double seconds = 0.0;  // device time spent in evaluate so far (the sources add to it)
};

// The full estimate on `map` (kept by reference: it must outlive the source); maxK ≥ every
// query's k. scene: needed when settings.visibility is on. Records are PclEstimate (stride 8).
std::shared_ptr<IrradianceSource> estimateIrradianceSource(const PhotonMapOnDevice& map, uint32_t maxK,
                                                           const EstimateSettings& settings, const DeviceScene* scene);

// Christensen's lookup on `map` (kept by reference); records are float4 (stride 4). The
// query's k is unused.
std::shared_ptr<IrradianceSource> precomputedIrradianceSource(const DeviceIrradianceMap& map);

}  // namespace pcl
