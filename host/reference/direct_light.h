// CPU twin of the direct-light stage (kernels/README.md, "Eye pass: direct light").
#pragma once
#include <vector>

#include "geometry/scene_geometry.h"
#include "prep/area_light_table.h"
#include "prep/scene_buffers.h"
#include "shared/types.h"

namespace pcl {

// cdf: the record's importance histogram table (G² floats) when params.histogramCells > 0.
PclRadiance referenceDirectLightAt(const SceneGeometry& geometry, const SceneBuffers& buffers,
                                   const AreaLightTable& table, const PclDirectParams& params, const PclEyeHit& h,
                                   const float* cdf = nullptr);
std::vector<PclRadiance> referenceDirectLight(const SceneGeometry& geometry, const SceneBuffers& buffers,
                                              const std::vector<PclEyeHit>& hits, const PclDirectParams& params,
                                              const std::vector<float>* histograms = nullptr);

}  // namespace pcl
