// The plan (host/prep/plan.h): light paths present and the maps and samplers a scene needs,
// for every shipped scene and for small scenes built to exercise each rule; and the
// `photoncl analyze` command.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "common/test_scenes.h"
#include "prep/environment_map.h"
#include "prep/prepared_scene.h"
#include "run_photoncl.h"
#include "scene/load_scene.h"

namespace pcl {
namespace {

std::string scenePath(const std::string& name) { return std::string(PHOTONCL_SOURCE_DIR) + "/scenes/" + name; }

bool path(const LightPaths& lp, const std::string& notation) {
    for (const LightPath& p : lp.list)
        if (p.notation == notation) return p.present;
    ADD_FAILURE() << "no light path " << notation;
    return false;
}

PreparedScene analyzeFile(const std::string& name) {
    Scene s = loadScene(scenePath(name));
    PreparedScene a = prepareScene(s);
    std::printf("%s", formatPlan(s, a.paths, a.plan).c_str());
    return a;
}

// ---- Scenes built in code -------------------------------------------------------------------

using test_scenes::addQuad;
using test_scenes::addSphere;
using test_scenes::pointLight;

PlanSettings planSettingsForFg() {
    PlanSettings p;
    p.skyCaustics = false;
    return p;
}

// Materials here have Phong exponent 40.
int addMaterial(Scene& s, Vec3 rhoD, Vec3 rhoS = Vec3(0.0f), SpecularKind kind = SpecularKind::None,
                Vec3 emission = Vec3(0.0f)) {
    return test_scenes::addMaterial(s, rhoD, rhoS, kind, emission, 40.0f);
}

// An empty scene with a pinhole camera looking down at the origin from above and in front.
Scene base() {
    Scene s;
    s.path = "built-in";
    s.camera.position = Vec3(0, 2, -4);
    s.camera.lookAt = Vec3(0, 0, 0);
    return s;
}

// A diffuse floor quad (two coplanar triangles) facing up under a point light.
Scene floorUnderPointLight() {
    Scene s = base();
    int white = addMaterial(s, Vec3(0.7f));
    addQuad(s, Vec3(-2, 0, -2), Vec3(0, 0, 4), Vec3(4, 0, 0), white);
    s.lights = {pointLight(Vec3(0, 2, 0))};
    return s;
}

// A diffuse floor and back wall under a point light: they light each other.
Scene diffuseRoom() {
    Scene s = floorUnderPointLight();
    addQuad(s, Vec3(-2, 0, 2), Vec3(0, 3, 0), Vec3(4, 0, 0), 0);
    return s;
}

// ---- Shipped scenes -------------------------------------------------------------------------

TEST(PlanShipped, CornellBox) {
    PreparedScene a = analyzeFile("cornell-box.json");
    EXPECT_TRUE(path(a.paths, "LE"));
    EXPECT_TRUE(path(a.paths, "LDE"));
    EXPECT_FALSE(path(a.paths, "LS+E"));
    EXPECT_FALSE(path(a.paths, "LS+DE"));
    EXPECT_TRUE(path(a.paths, "LD(S|D)*DE"));
    EXPECT_TRUE(a.plan.globalMap);
    EXPECT_GT(a.plan.globalPhotons, 0u);
    EXPECT_FALSE(a.plan.causticMap);
    EXPECT_EQ(a.plan.causticPhotons, 0u);
    EXPECT_TRUE(a.plan.finalGather);
    EXPECT_FALSE(a.plan.lensSampling);
    EXPECT_FALSE(a.plan.timeSampling);
    EXPECT_TRUE(a.plan.areaLightSampling);
    EXPECT_FALSE(a.plan.glossySampling);
}

TEST(PlanShipped, CornellSpheres) {
    for (const char* name : {"cornell-spheres.json", "cornell-spheres-point.json"}) {
        PreparedScene a = analyzeFile(name);
        bool area = std::string(name) == "cornell-spheres.json";
        EXPECT_EQ(path(a.paths, "LE"), area) << name;  // a point light is not visible
        EXPECT_TRUE(path(a.paths, "LS+E")) << name;
        EXPECT_TRUE(path(a.paths, "LDS+E")) << name;
        EXPECT_TRUE(path(a.paths, "LS+DE")) << name;
        EXPECT_TRUE(a.plan.causticMap) << name;
        EXPECT_GT(a.plan.causticPhotons, 0u) << name;
        EXPECT_TRUE(a.plan.globalMap) << name;
        EXPECT_FALSE(a.plan.lensSampling) << name;
        EXPECT_FALSE(a.plan.timeSampling) << name;
        EXPECT_EQ(a.plan.areaLightSampling, area) << name;
        EXPECT_FALSE(a.plan.glossySampling) << name;
    }
}

TEST(PlanShipped, CornellGlossyGetsACausticMapFromItsMixedFloor) {
    // The glossy floor also has a diffuse part; the caustic pass bounces photons off its glossy
    // lobe onto the walls (light → floor → wall, LSD), so the scene needs a caustic map.
    PreparedScene a = analyzeFile("cornell-glossy.json");
    EXPECT_TRUE(path(a.paths, "LS+DE"));
    EXPECT_TRUE(a.plan.causticMap);
    EXPECT_GT(a.plan.causticPhotons, 0u);
    EXPECT_NE(a.plan.reasons[1].find("caustics (LS+DE)"), std::string::npos) << a.plan.reasons[1];
    EXPECT_TRUE(a.plan.globalMap);
    EXPECT_TRUE(a.plan.glossySampling);
    EXPECT_FALSE(a.plan.lensSampling);
    EXPECT_FALSE(a.plan.timeSampling);
}

TEST(PlanShipped, MotionDof) {
    PreparedScene a = analyzeFile("motion-dof.json");
    EXPECT_TRUE(a.plan.lensSampling);
    EXPECT_TRUE(a.plan.timeSampling);
    EXPECT_TRUE(a.plan.causticMap);  // the chrome sphere, in reach of the lamp and the sun
    EXPECT_TRUE(a.plan.globalMap);
    EXPECT_TRUE(a.plan.glossySampling);  // gold
    EXPECT_TRUE(a.plan.areaLightSampling);
}

// fg leaves a spread sky's caustics to its gather rays (PlanSettings::skyCaustics): sky-spheres'
// only caustic light is its constant sky, so fg needs no caustic map there and the sky sends no
// caustic photons; the courtyard's sky holds a sun (its caustic through the glass ball would be
// a firefly to a gather ray), so it keeps them. progressive (the default settings) keeps both.
TEST(PlanShipped, FgLeavesASpreadSkysCausticsToTheGatherRays) {
    for (const char* name : {"sky-spheres.json", "courtyard/courtyard.json"}) {
        const Scene s = loadScene(scenePath(name));
        const PreparedScene fg = prepareScene(s, planSettingsForFg());
        const PreparedScene other = prepareScene(s);
        uint32_t skyCells = 0;
        for (const PclLight& l : fg.buffers.lights)
            if (l.type == PCL_LIGHT_ENVIRONMENT) skyCells += l.projCount;
        const bool spread = std::string(name) == "sky-spheres.json";
        EXPECT_EQ(skyCausticsByEyeRays(s), spread) << name;
        EXPECT_EQ(fg.plan.causticMap, !spread) << name;
        EXPECT_EQ(skyCells > 0, !spread) << name;
        EXPECT_TRUE(other.plan.causticMap) << name;
        EXPECT_TRUE(path(fg.paths, "LS+E")) << name << ": the sky is still seen in the mirror";
    }
}

#if PHOTONCL_HAVE_GLTF
TEST(PlanShipped, GltfRoom) {
    PreparedScene a = analyzeFile("gltf-room.gltf");
    EXPECT_TRUE(a.plan.causticMap);  // mirror, glass
    EXPECT_TRUE(a.plan.globalMap);
    EXPECT_TRUE(a.plan.glossySampling);
    EXPECT_TRUE(a.plan.areaLightSampling);
    EXPECT_FALSE(a.plan.lensSampling);
    EXPECT_FALSE(a.plan.timeSampling);
}
#endif

// ---- One rule at a time -------------------------------------------------------------------

TEST(PlanRules, NoSpecularSurfacesNoCausticMap) {
    PreparedScene a = prepareScene(diffuseRoom());
    EXPECT_FALSE(path(a.paths, "LS+DE"));
    EXPECT_FALSE(a.plan.causticMap);
    EXPECT_EQ(a.plan.reasons[1], "no specular surfaces");
    EXPECT_TRUE(a.plan.globalMap);  // floor and wall light each other
    EXPECT_FALSE(a.plan.areaLightSampling);
    EXPECT_FALSE(path(a.paths, "LE"));
}

TEST(PlanRules, SingleDiffusePlaneNeedsNoGlobalMap) {
    PreparedScene a = prepareScene(floorUnderPointLight());
    EXPECT_TRUE(path(a.paths, "LDE"));
    EXPECT_FALSE(path(a.paths, "LD(S|D)*DE"));
    EXPECT_FALSE(a.plan.globalMap);
    EXPECT_EQ(a.plan.globalPhotons, 0u);
    EXPECT_FALSE(a.plan.finalGather);
    EXPECT_FALSE(a.plan.causticMap);

    // Two meshes in one plane (a tiled floor) still cannot light each other ...
    Scene tiled = floorUnderPointLight();
    addQuad(tiled, Vec3(2, 0, -2), Vec3(0, 0, 4), Vec3(3, 0, 0), 0);
    EXPECT_FALSE(prepareScene(tiled).plan.globalMap);
    // ... nor can a single diffuse sphere (convex) ...
    Scene ball = base();
    addSphere(ball, Vec3(0, 0.5f, 0), 0.5f, addMaterial(ball, Vec3(0.5f)));
    ball.lights = {pointLight(Vec3(0, 3, 0))};
    EXPECT_FALSE(prepareScene(ball).plan.globalMap);
    // ... though its inside lights itself when the light is in it (the furnace) ...
    Scene furnace = base();
    addSphere(furnace, Vec3(0, 0, 0), 1.0f, addMaterial(furnace, Vec3(0.5f)));
    furnace.lights = {pointLight(Vec3(0, 0.2f, 0))};
    EXPECT_TRUE(prepareScene(furnace).plan.globalMap);
    // ... but a second, tilted plane can.
    Scene two = floorUnderPointLight();
    addQuad(two, Vec3(-2, 0, 2), Vec3(0, 2, 0.5f), Vec3(4, 0, 0), 0);
    EXPECT_TRUE(prepareScene(two).plan.globalMap);
}

TEST(PlanRules, MirrorReturningLightToTheFloorNeedsGlobalAndCausticMaps) {
    Scene s = floorUnderPointLight();
    addSphere(s, Vec3(0.5f, 0.5f, 0), 0.4f, addMaterial(s, Vec3(0.0f), Vec3(0.9f), SpecularKind::Mirror));
    PreparedScene a = prepareScene(s);
    EXPECT_TRUE(path(a.paths, "LS+DE"));
    EXPECT_TRUE(a.plan.causticMap);
    EXPECT_TRUE(path(a.paths, "LD(S|D)*DE"));  // floor → mirror → floor
    EXPECT_TRUE(a.plan.globalMap);
}

TEST(PlanRules, MirrorAloneNothingDiffuseBuildsNoMaps) {
    Scene s = base();
    addSphere(s, Vec3(0, 0.5f, 0), 0.5f, addMaterial(s, Vec3(0.0f), Vec3(0.9f), SpecularKind::Mirror));
    s.lights = {pointLight(Vec3(0, 3, 0))};
    PreparedScene a = prepareScene(s);
    EXPECT_TRUE(path(a.paths, "LS+E"));
    EXPECT_FALSE(path(a.paths, "LDE"));
    EXPECT_FALSE(path(a.paths, "LS+DE"));
    EXPECT_FALSE(a.plan.globalMap);
    EXPECT_FALSE(a.plan.causticMap);
    EXPECT_FALSE(a.plan.finalGather);
    EXPECT_EQ(a.plan.globalPhotons + a.plan.causticPhotons, 0u);
}

TEST(PlanRules, SpecularOutOfTheLightsReachNoCausticMap) {
    // A spot light aimed at the floor, a mirror sphere above and behind it.
    Scene s = diffuseRoom();
    addSphere(s, Vec3(0, 2.6f, 0), 0.3f, addMaterial(s, Vec3(0.0f), Vec3(0.9f), SpecularKind::Mirror));
    Light spot;
    spot.type = LightType::Spot;
    spot.position = Vec3(0, 2, 0);
    spot.direction = Vec3(0, -1, 0);
    spot.intensity = Vec3(1.0f);
    spot.cosInner = std::cos(0.3f);
    spot.cosOuter = std::cos(0.6f);
    s.lights = {spot};
    PreparedScene a = prepareScene(s);
    EXPECT_EQ(a.paths.markedCells, 0u);
    EXPECT_FALSE(path(a.paths, "LS+E"));
    EXPECT_FALSE(a.plan.causticMap);
    EXPECT_NE(a.plan.reasons[1].find("projection map"), std::string::npos) << a.plan.reasons[1];
    // Turned towards it, the same light reaches it.
    s.lights[0].direction = Vec3(0, 1, 0);
    EXPECT_TRUE(prepareScene(s).plan.causticMap);
}

TEST(PlanRules, GlassRefractingOntoTheFloorNeedsACausticMap) {
    Scene s = floorUnderPointLight();
    addSphere(s, Vec3(0, 0.6f, 0), 0.4f, addMaterial(s, Vec3(0.0f), Vec3(1.0f), SpecularKind::Dielectric));
    EXPECT_TRUE(prepareScene(s).plan.causticMap);
}

TEST(PlanRules, ThinLensMeansLensSampling) {
    Scene s = diffuseRoom();
    EXPECT_FALSE(prepareScene(s).plan.lensSampling);
    s.camera.model = CameraModel::ThinLens;
    s.camera.apertureRadius = 0.05f;
    s.camera.focusDistance = 4.0f;
    RenderPlan p = prepareScene(s).plan;
    EXPECT_TRUE(p.lensSampling);
    EXPECT_NE(p.reasons[3].find("thin lens"), std::string::npos);
}

TEST(PlanRules, MotionMeansTimeSampling) {
    Scene s = diffuseRoom();
    EXPECT_FALSE(prepareScene(s).plan.timeSampling);
    addSphere(s, Vec3(0, 0.5f, 0), 0.3f, 0, Vec3(0.5f, 0, 0));
    s.camera.shutterClose = 0.01f;
    EXPECT_TRUE(prepareScene(s).plan.timeSampling);
    s.camera.shutterClose = 0.0f;  // motion, but the shutter never opens
    EXPECT_FALSE(prepareScene(s).plan.timeSampling);
}

TEST(PlanRules, AreaLightsAndGlossySurfacesTurnOnTheirSamplers) {
    Scene s = diffuseRoom();
    int lamp = addMaterial(s, Vec3(0.0f), Vec3(0.0f), SpecularKind::None, Vec3(5.0f));
    Light area;
    area.type = LightType::Area;
    area.mesh = addQuad(s, Vec3(-0.3f, 2.9f, -0.3f), Vec3(0.6f, 0, 0), Vec3(0, 0, 0.6f), lamp);  // faces down
    s.lights = {area};
    PreparedScene a = prepareScene(s);
    EXPECT_TRUE(a.plan.areaLightSampling);
    EXPECT_FALSE(a.plan.glossySampling);
    EXPECT_TRUE(path(a.paths, "LE"));  // the camera (y = 2) is below the lamp (y = 2.9), on its lit side
    addSphere(s, Vec3(0, 0.5f, 0), 0.4f, addMaterial(s, Vec3(0.3f), Vec3(0.4f), SpecularKind::Glossy));
    a = prepareScene(s);
    EXPECT_TRUE(a.plan.glossySampling);
    EXPECT_TRUE(a.plan.causticMap);  // glossy with a diffuse part still reflects onto floor and wall
}

TEST(PlanRules, MixedSurfaceMakesCausticsWhenItSeesADiffuseOne) {
    // A single glossy-and-diffuse floor under a point light: its glossy lobe sends light away,
    // onto nothing, so no LS+D path exists ...
    Scene s = base();
    int mixed = addMaterial(s, Vec3(0.4f), Vec3(0.5f), SpecularKind::Glossy);
    addQuad(s, Vec3(-2, 0, -2), Vec3(0, 0, 4), Vec3(4, 0, 0), mixed);
    s.lights = {pointLight(Vec3(0, 2, 0))};
    PreparedScene a = prepareScene(s);
    EXPECT_TRUE(path(a.paths, "LS+E"));
    EXPECT_FALSE(path(a.paths, "LS+DE"));
    EXPECT_FALSE(a.plan.causticMap);
    EXPECT_EQ(a.plan.reasons[1], "specular and diffuse surfaces cannot see each other");
    // ... a diffuse wall receives what the floor reflects (light → floor → wall) ...
    Scene wall = s;
    addQuad(wall, Vec3(-2, 0, 2), Vec3(0, 3, 0), Vec3(4, 0, 0), addMaterial(wall, Vec3(0.7f)));
    a = prepareScene(wall);
    EXPECT_TRUE(path(a.paths, "LS+DE"));
    EXPECT_TRUE(a.plan.causticMap);
    EXPECT_NE(a.plan.reasons[1].find("caustics (LS+DE)"), std::string::npos) << a.plan.reasons[1];
    // ... and so does a mixed wall (light → floor → wall, or light → wall → floor).
    Scene mixedWall = s;
    addQuad(mixedWall, Vec3(-2, 0, 2), Vec3(0, 3, 0), Vec3(4, 0, 0), mixed);
    EXPECT_TRUE(prepareScene(mixedWall).plan.causticMap);
}

TEST(PlanFormat, PrintsEveryPathAndOneReasonPerDecision) {
    Scene s = loadScene(scenePath("cornell-spheres.json"));
    PreparedScene a = prepareScene(s);
    ASSERT_EQ(a.plan.reasons.size(), 8u);
    for (const std::string& r : a.plan.reasons) EXPECT_FALSE(r.empty());
    std::string text = formatPlan(s, a.paths, a.plan);
    for (const char* key : {"LE ", "LDE ", "LS+E ", "LDS+E ", "LS+DE ", "LD(S|D)*DE ", "global map", "caustic map",
                            "final gather", "lens sampling", "time sampling", "area-light sampling", "glossy sampling",
                            "L(S|D|V)*V(S|D|V)*E ", "volume map"})
        EXPECT_NE(text.find(key), std::string::npos) << key << "\n" << text;
    for (const std::string& r : a.plan.reasons) EXPECT_NE(text.find(r), std::string::npos) << r;
}

// ---- photoncl analyze ------------------------------------------------------------------------

using photoncl_cli::Result;
using photoncl_cli::run;

TEST(AnalyzeCommand, PrintsThePlanOfCornellSpheres) {
    Result r = run("analyze " + scenePath("cornell-spheres.json"));
    EXPECT_EQ(r.status, 0) << r.output;
    Scene s = loadScene(scenePath("cornell-spheres.json"));
    PreparedScene a = prepareScene(s);
    EXPECT_EQ(r.output, formatPlan(s, a.paths, a.plan));  // the whole output, nothing else
    EXPECT_NE(r.output.find("LS+DE               yes"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("caustic map          yes, 100000 photons"), std::string::npos) << r.output;
}

TEST(AnalyzeCommand, BadInputExitsTwo) {
    Result missing = run("analyze " + scenePath("no-such-scene.json"));
    EXPECT_EQ(missing.status, 2);
    EXPECT_NE(missing.output.find("no-such-scene.json"), std::string::npos) << missing.output;
    EXPECT_EQ(run("analyze").status, 2);
    EXPECT_EQ(run("analyze " + scenePath("cornell-box.json") + " --global-photons 0").status, 2);
    EXPECT_EQ(run("analyze " + scenePath("cornell-box.json") + " --bogus").status, 2);
    EXPECT_EQ(run("analyze --help").status, 0);
}

}  // namespace
}  // namespace pcl
