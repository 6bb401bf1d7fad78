// CPU twin of the eye-path stage (kernels/README.md, "Eye pass: eye paths"), written from the
// README with the reference BSDF helpers and the reference Sampler's dimensions.
#pragma once
#include <vector>

#include "geometry/scene_geometry.h"
#include "prep/area_light_table.h"
#include "prep/scene_buffers.h"
#include "shared/types.h"

namespace pcl {

PclEyeHit referenceEyePath(const SceneGeometry& geometry, const SceneBuffers& buffers, const AreaLightTable& table,
                           const PclEyeParams& params, const PclRay& ray, uint32_t i);
std::vector<PclEyeHit> referenceEyePaths(const SceneGeometry& geometry, const SceneBuffers& buffers,
                                         const std::vector<PclRay>& rays, const PclEyeParams& params);

}  // namespace pcl
