#include "prep/prepared_scene.h"

#include "prep/projection_map.h"

namespace pcl {

PreparedScene prepareScene(const Scene& scene, const PlanSettings& settings) {
    PreparedScene p;
    p.geometry = SceneGeometry::build(scene);
    p.buffers = buildSceneBuffers(scene, p.geometry);
    buildProjectionMaps(scene, p.geometry, p.buffers);
    p.paths = classifyLightPaths(scene, p.geometry, p.buffers);
    p.plan = makePlan(scene, p.paths, settings);
    // After the paths: the sky is still seen in the specular surfaces (LS+E).
    if (!p.plan.skyCausticPhotons) clearSkyProjection(p.buffers);
    return p;
}

}  // namespace pcl
