// CPU twin of the eye-path stage (kernels/README.md, "Eye pass: eye paths"), written from the
// README with the reference BSDF helpers and the reference Sampler's dimensions.
#pragma once
#include <vector>

#include "geometry/scene_geometry.h"
#include "prep/area_light_table.h"
#include "prep/scene_buffers.h"
#include "shared/types.h"

namespace pcl {

// The medium segments of a chunk's records (scenes with media), laid out as the kernel's:
// segments[c · records + i] for c < counts[i] ≤ perRecord.
struct EyeVolumeSegments {
    uint32_t perRecord = 0;  // PclEyeParams::volumeSegments
    std::vector<PclVolumeSegment> segments;
    std::vector<uint32_t> counts;
};

// Record i of the chunk; its medium segments, in order, in *segments when given.
PclEyeHit referenceEyePath(const SceneGeometry& geometry, const SceneBuffers& buffers, const AreaLightTable& table,
                           const PclEyeParams& params, const PclRay& ray, uint32_t i,
                           std::vector<PclVolumeSegment>* segments = nullptr);
std::vector<PclEyeHit> referenceEyePaths(const SceneGeometry& geometry, const SceneBuffers& buffers,
                                         const std::vector<PclRay>& rays, const PclEyeParams& params,
                                         EyeVolumeSegments* segments = nullptr);

}  // namespace pcl
