// The triangle lights as one discrete distribution, for direct light by shadow rays
// (kernels/direct_light.cl, reference/direct_light): cdf[l] = Σ_{j ≤ l} s_j / S over the light
// list (s_j = (Φr + Φg + Φb)/3 of triangle lights, 0 for the others; float, the last triangle
// light's entry exactly 1), S = total (float); lightOfPrim[prim] = the light index of an
// emitting triangle, PCL_NO_HIT otherwise. Kernel and twin read the same table, so both pick
// the same triangle from the same random number.
#pragma once
#include <cstdint>
#include <vector>

#include "prep/scene_buffers.h"

namespace pcl {

struct AreaLightTable {
    std::vector<float> cdf;
    std::vector<uint32_t> lightOfPrim;
    float total = 0.0f;
    uint32_t areaLights = 0;
};

AreaLightTable buildAreaLightTable(const SceneBuffers& buffers, size_t primitiveCount);

}  // namespace pcl
