// host/prep/: what the device stages (pipeline/) and the CPU twin (reference/) both consume,
// and nothing that knows OpenCL: the flat scene buffers, projection maps, photon allocation, the
// area-light table, the estimate settings with the filter norms, the search structure's name
// and the plan. This is all the twin shares with the kernels besides shared/types.h and
// shared/rng.h; every stage's computation it re-derives (kernels/README.md, "What the twin
// shares with the kernels, and why").
//
// PreparedScene: a scene made ready for rendering and checking, once: the BVH (geometry), the
// flat buffers with their projection maps, the light paths the scene can produce and the plan
// that follows from them (which maps and samplers a render uses). `render`, `batch`, `check`,
// `analyze`, `photons`, `sweep` and the tests start from it.
#pragma once
#include "geometry/scene_geometry.h"
#include "prep/plan.h"
#include "prep/scene_buffers.h"
#include "scene/scene.h"

namespace pcl {

struct PreparedScene {
    SceneGeometry geometry;
    SceneBuffers buffers;  // projection maps included
    LightPaths paths;
    RenderPlan plan;
};

PreparedScene prepareScene(const Scene& scene, const PlanSettings& settings = {});

}  // namespace pcl
