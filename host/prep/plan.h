// Model no more than the scene needs: classify the light paths a
// scene can produce in Heckbert's notation L(S|D)*E (SEED-global-illumination-notes.md, "Light
// Paths"), then decide which photon maps are built and which eye-pass samplers run.
//
// The classification is conservative: a path class is called present when the scene's lights,
// materials and (cheap) geometry allow it, not when a simulation has found it. Geometry enters in
// three places only:
//  * reach from the lights: the projection maps (prep/projection_map.h) say whether a
//    light can send photons straight at a specular object;
//  * "can see each other": two primitives are taken to see each other when they are distinct and
//    not both triangles of one plane, and a sphere with a light inside sees itself (the furnace).
//    So one diffuse triangle or convex sphere, or diffuse triangles all in one plane (a floor,
//    however many triangles), cannot interreflect; anything else is assumed to
//    (back-to-back or occluded surfaces are not detected);
//  * visible emitters: an emitting triangle whose lit side faces the camera position.
// Participating media add V, a scattering event in a medium: volume paths L(S|D|V)*V(S|D|V)*E are
// present when a medium in use scatters (σs > 0 in some channel) and the scene is lit; where the
// medium sits is not checked against the lights.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "geometry/scene_geometry.h"
#include "prep/scene_buffers.h"
#include "scene/scene.h"

namespace pcl {

struct LightPath {
    std::string notation;  // e.g. "LS+DE"
    std::string name;      // e.g. "caustics"
    bool present = false;
    std::string why;  // the rule that decided it, with the scene's objects
};

// What the scene holds that decides the plan (primitives counted, not materials, so an
// unused material changes nothing).
struct LightPaths {
    bool visibleEmitters = false;    // LE
    bool direct = false;             // LDE
    bool specularOfLights = false;   // LS+E
    bool diffuseInSpecular = false;  // LDS+E
    bool caustics = false;           // LS+DE
    bool indirectDiffuse = false;    // LD(S|D)*DE
    bool volume = false;             // L(S|D|V)*V(S|D|V)*E: light scattered in a medium
    // Facts behind them.
    size_t lights = 0, areaTriangles = 0, diffusePrims = 0, specularPrims = 0, pureSpecularPrims = 0, glossyPrims = 0;
    uint32_t markedCells = 0;  // projection-map cells over all lights (specular surfaces, mixed included)
    uint32_t skyCells = 0;     // of those, the sky's
    bool skySpread = false;    // the sky's light is spread over ≥ kSpreadSkySolidAngle (skyCausticsByEyeRays)
    bool diffuseSeesDiffuse = false, diffuseSeesSpecular = false;
    size_t media = 0, scatteringMedia = 0;  // media in use (global or in a shape), those with σs > 0
    std::vector<LightPath> list;            // the classes above, in order, with reasons
};

struct PlanSettings {
    uint32_t globalPhotons = 200000;   // photons emitted in the global pass when one is needed
    uint32_t causticPhotons = 100000;  // photons emitted in the caustic pass when one is needed
    // false: a spread sky (LightPaths::skySpread) sends no caustic photons (RenderPlan::
    // skyCausticPhotons; prepareScene clears its projection map), so its caustics are left to the
    // eye side; fg's gather rays then find them through the specular surfaces, as a path tracer
    // does (a large, smooth light: sky-spheres' caustic part held 99 % of fg's variance as
    // photons). progressive and direct read caustics from the map only and keep the sky's photons.
    bool skyCaustics = true;
};

struct RenderPlan {
    bool globalMap = false, causticMap = false, finalGather = false;
    bool lensSampling = false, timeSampling = false, areaLightSampling = false, glossySampling = false;
    // Volume photons at scattering events in media (Jensen & Christensen 1998), planned only
    // when a medium scatters; the global pass stores them (the caustic pass the volume caustics),
    // so volumePhotons is the global pass's photon count. progressive and direct read them; fg
    // refuses media (prep/media_support.h).
    bool volumeMap = false;
    // The sky sends caustic photons (it reaches specular surfaces, and PlanSettings::skyCaustics or
    // its light is not spread); false: prepareScene clears its projection map.
    bool skyCausticPhotons = false;
    uint32_t globalPhotons = 0, causticPhotons = 0, volumePhotons = 0;
    // One reason per decision, in the order of the fields above: global map, caustic map, final
    // gather, lens, time, area light, glossy, volume map.
    std::vector<std::string> reasons;
};

// buffers must hold projection maps (buildProjectionMaps).
LightPaths classifyLightPaths(const Scene& scene, const SceneGeometry& geometry, const SceneBuffers& buffers);
RenderPlan makePlan(const Scene& scene, const LightPaths& paths, const PlanSettings& settings = {});

// The light paths present and the plan with one reason per decision (what `photoncl analyze`
// prints and `render` logs).
std::string formatPlan(const Scene& scene, const LightPaths& paths, const RenderPlan& plan);

}  // namespace pcl
