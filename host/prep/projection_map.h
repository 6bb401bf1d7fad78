// Projection maps (Jensen 1996, "Global Illumination using Photon Maps", §3.1; Jensen 2001 §5.2.2):
// per light, a PCL_PROJ_GRID × PCL_PROJ_GRID grid over the unit square of the light's sample
// (the pair (s1, s2) its warp turns into a direction, or into a disc position for directional
// lights; kernels/README.md "emit"). A cell is marked when some sample in it can send a photon
// straight at a specular object, so the caustic pass emits only into marked cells.
//
// The map is conservative: every sample whose first hit is specular lies in a marked cell
// (tests/unit/projection_map_test.cpp checks this by brute force), so restricting caustic
// photons to marked cells and scaling their flux by the marked fraction adds no bias.
#pragma once
#include <cstdint>
#include <vector>

#include "geometry/scene_geometry.h"
#include "prep/scene_buffers.h"
#include "scene/scene.h"

namespace pcl {

// What the projection maps aim at: photons reflect or refract specularly off a material with
// ρs > 0 and a specular kind (mirror, glossy, dielectric), whether or not it also has a diffuse part.
bool isSpecular(const PclMaterial& m);
bool isDiffuse(const PclMaterial& m);  // max ρd > 0

// Fills buffers.projCells and every light's projFirst/projCount (cells in increasing index
// k = cy·G + cx, with cx = ⌊s1·G⌋, cy = ⌊s2·G⌋). A scene without specular objects gets
// projCount 0 everywhere. buffers must come from buildSceneBuffers(scene, geometry).
void buildProjectionMaps(const Scene& scene, const SceneGeometry& geometry, SceneBuffers& buffers);

// Whether the sky sends caustic photons (its projection map is not empty; PlanSettings::skyCaustics
// clears it): fg's gather rays then leave the sky they reach through specular surfaces to the
// caustic map (PclGatherParams::causticSky).
bool skySendsCausticPhotons(const SceneBuffers& buffers);

// Clears the sky's projection map: it then sends no caustic photons (prepareScene, where the
// plan says so: RenderPlan::skyCausticPhotons).
void clearSkyProjection(SceneBuffers& buffers);

bool isPureSpecular(const PclMaterial& m);  // specular with ρd = 0

// The light's warp of kernels/README.md "emit" in double precision: the direction of sample
// (s1, s2) (point, spot, triangle) and the origin for triangle lights at position numbers
// (u1, u2) and time τ, or for directional lights the disc position of (s1, s2).
struct LightSampleRay {
    Vec3 origin, direction;
};
LightSampleRay warpLightSample(const PclLight& light, double s1, double s2, double u1, double u2, double time);

// The share of a light's flux its caustic photons carry (kernels/README.md, "Photon
// allocation"): the marked fraction of its sample square, fᵢ = projCount / G², times for the sky
// aimed at its target ball (PclLight.e1) that disc's share of the scene's, (r / R)².
inline double projectionFraction(const PclLight& light) {
    const double f = double(light.projCount) / double(PCL_PROJ_GRID * PCL_PROJ_GRID);
    if (light.type != PCL_LIGHT_ENVIRONMENT || !(light.e1[3] > 0.0f)) return f;
    const double share = double(light.e1[3]) / double(light.radius);
    return f * share * share;
}

}  // namespace pcl
