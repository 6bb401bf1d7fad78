// Participating media in the scene model: the JSON keys (scenes/README.md, "media"), the checks
// that refuse bad values with the usual "FILE: FIELD: expected X, got Y", the closed-mesh test a
// medium's boundary must pass, which medium lies on either side of every surface
// (prep/medium_boundaries.h), and the photon methods refusing media until the volume photon map
// lands.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "geometry/scene_geometry.h"
#include "prep/media_support.h"
#include "prep/medium_boundaries.h"
#include "scene/json_loader.h"
#include "scene/mesh_topology.h"
#include "scene/validate.h"

using nlohmann::json;
using namespace pcl;

namespace {

// The unit cube [0,1]³ as 12 outward-facing triangles (counter-clockwise seen from outside).
json cubePositions() { return json::array({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1}); }
json cubeIndices() {
    return json::array(
        {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 2, 3, 7, 2, 7, 6, 1, 2, 6, 1, 6, 5, 0, 4, 7, 0, 7, 3});
}

// A small valid scene: fog everywhere, a glass ball of milk, a smoke cube with no surface.
json mediaScene() {
    return json{
        {"camera", {{"position", {0, 0.5, 5}}, {"look_at", {0, 0.5, 0}}, {"fov", 40}, {"resolution", {8, 8}}}},
        {"materials", json::array({{{"name", "white"}, {"rho_d", {0.5, 0.5, 0.5}}},
                                   {{"name", "glass"}, {"specular", {{"kind", "dielectric"}, {"ior", 1.33}}}}})},
        {"media", json::array({{{"name", "fog"}, {"sigma_a", {0.01, 0.01, 0.01}}, {"sigma_s", {0.1, 0.1, 0.1}}},
                               {{"name", "milk"}, {"sigma_a", {0.1, 0.2, 0.3}}, {"sigma_s", {20, 21, 22}}, {"g", 0.8}},
                               {{"name", "smoke"}, {"sigma_s", {2, 2, 2}}, {"g", -0.3}}})},
        {"medium", "fog"},
        {"shapes", json::array({{{"type", "quad"},
                                 {"material", "white"},
                                 {"corner", {-5, 0, -5}},
                                 {"edge_u", {0, 0, 10}},
                                 {"edge_v", {10, 0, 0}}},
                                {{"type", "sphere"},
                                 {"name", "ball"},
                                 {"material", "glass"},
                                 {"medium", "milk"},
                                 {"centre", {-1, 1, 0}},
                                 {"radius", 0.5}},
                                {{"type", "mesh"},
                                 {"name", "cube"},
                                 {"medium", "smoke"},
                                 {"positions", cubePositions()},
                                 {"indices", cubeIndices()}}})},
        {"lights", json::array({{{"type", "point"}, {"position", {0, 3, 0}}, {"power", {100, 100, 100}}}})}};
}

Scene load(const json& j) {
    Scene s = parseJsonScene(j.dump(), "media.json");
    validateScene(s);
    return s;
}

// Loading `j` must throw InputError whose message holds every fragment.
void expectError(const json& j, std::initializer_list<std::string> fragments) {
    try {
        load(j);
        ADD_FAILURE() << "expected InputError, loaded fine: " << j.dump().substr(0, 200);
    } catch (const InputError& e) {
        std::string msg = e.what();
        EXPECT_EQ(msg.rfind("media.json: ", 0), 0u) << msg;
        for (const std::string& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' in: " << msg;
    }
}

}  // namespace

TEST(MediumScene, LoadsMediaShapesAndTheGlobalMedium) {
    Scene s = load(mediaScene());
    ASSERT_EQ(s.media.size(), 3u);
    EXPECT_EQ(s.media[1].name, "milk");
    EXPECT_EQ(s.media[1].sigmaA, Vec3(0.1f, 0.2f, 0.3f));
    EXPECT_EQ(s.media[1].sigmaS, Vec3(20.0f, 21.0f, 22.0f));
    EXPECT_FLOAT_EQ(s.media[1].g, 0.8f);
    EXPECT_EQ(s.media[2].sigmaA, Vec3(0.0f));  // sigma_a defaults to 0
    EXPECT_EQ(s.globalMedium, 0);
    ASSERT_EQ(s.spheres.size(), 1u);
    EXPECT_EQ(s.spheres[0].medium, 1);
    EXPECT_EQ(s.materials[size_t(s.spheres[0].material)].name, "glass");
    ASSERT_EQ(s.meshes.size(), 2u);
    EXPECT_EQ(s.meshes[0].medium, -1);
    EXPECT_EQ(s.meshes[1].medium, 2);
    // No material: an invisible boundary that neither reflects nor emits.
    const Material& boundary = s.materials[size_t(s.meshes[1].material)];
    EXPECT_TRUE(boundary.interface);
    EXPECT_EQ(boundary.rhoD, Vec3(0.0f));
    EXPECT_FALSE(boundary.emits());
    EXPECT_TRUE(s.hasMedia());
}

TEST(MediumScene, RefusesBadValues) {
    auto with = [](auto edit) {
        json j = mediaScene();
        edit(j);
        return j;
    };
    expectError(with([](json& j) {
                    j["media"][1]["sigma_a"] = {-0.1, 0, 0};
                }),
                {"media[1].sigma_a", "expected 3 finite numbers >= 0 (1/m)", "got [-0.1,0,0]"});
    expectError(with([](json& j) {
                    j["media"][0]["sigma_s"] = {0, -2, 0};
                }),
                {"media[0].sigma_s", "expected 3 finite numbers >= 0", "got [0,-2,0]"});
    expectError(with([](json& j) { j["media"][1]["g"] = 1.0; }),
                {"media[1].g", "expected a Henyey-Greenstein g in (-1, 1)", "got 1.0"});
    expectError(with([](json& j) { j["media"][1]["g"] = -1.5; }), {"media[1].g", "in (-1, 1)", "got -1.5"});
    expectError(with([](json& j) {
                    j["media"][2]["sigma_s"] = {0, 0, 0};
                }),
                {"media[2]", "sigma_a + sigma_s > 0 in some channel", "got all zero"});
    expectError(with([](json& j) { j["media"][2]["name"] = "fog"; }),
                {"media[2].name", "a name not used by another medium", "\"fog\" again"});
    expectError(with([](json& j) { j["media"][0]["density"] = 3; }), {"media[0].density", "unknown key"});
    expectError(with([](json& j) { j["medium"] = "smog"; }),
                {"medium: expected the name of a medium (fog, milk, smoke)", "got \"smog\""});
    expectError(with([](json& j) { j["shapes"][1]["medium"] = "cream"; }),
                {"shapes[1].medium", "the name of a medium", "got \"cream\""});
    // A quad is open: it cannot hold a medium.
    expectError(with([](json& j) { j["shapes"][0]["medium"] = "smoke"; }),
                {"meshes[0]", ".medium", "expected a closed mesh to hold medium \"smoke\"",
                 "is used by 1 triangle (the mesh is open)"});
    // The cube with one triangle left out is open; with one triangle turned round it is wound
    // inconsistently; with every triangle turned round it faces inward.
    expectError(with([](json& j) {
                    json idx = cubeIndices();
                    idx.erase(idx.end() - 3, idx.end());
                    j["shapes"][2]["indices"] = idx;
                }),
                {"meshes[1] (\"cube\").medium", "a closed mesh", "(the mesh is open)"});
    expectError(with([](json& j) { std::swap(j["shapes"][2]["indices"][1], j["shapes"][2]["indices"][2]); }),
                {"meshes[1] (\"cube\").medium", "inconsistent winding"});
    expectError(with([](json& j) {
                    json idx = cubeIndices();
                    for (size_t t = 0; t < idx.size(); t += 3) std::swap(idx[t + 1], idx[t + 2]);
                    j["shapes"][2]["indices"] = idx;
                }),
                {"meshes[1] (\"cube\").medium", "its triangles face inward (enclosed volume -1"});
    // Without a medium a shape still needs a material.
    expectError(with([](json& j) { j["shapes"][2].erase("medium"); }),
                {"shapes[2].material", "expected a material name, got nothing"});
}

TEST(MediumScene, ClosedMeshCheckWeldsSplitVertices) {
    // The cube with every triangle on its own three vertices (as per-face normals would split
    // it) is still closed.
    TriangleMesh m;
    json pos = cubePositions(), idx = cubeIndices();
    for (const auto& k : idx) {
        size_t v = k.get<size_t>();
        m.positions.push_back(Vec3(pos[3 * v].get<float>(), pos[3 * v + 1].get<float>(), pos[3 * v + 2].get<float>()));
        m.indices.push_back(uint32_t(m.indices.size()));
    }
    EXPECT_EQ(closedMeshProblem(m), "");
    EXPECT_NEAR(enclosedVolume(m), 1.0, 1e-9);
    m.indices.resize(m.indices.size() - 3);
    EXPECT_NE(closedMeshProblem(m).find("the mesh is open"), std::string::npos);
}

// Which medium is on either side of each surface, and where the camera is: fog outside, milk
// inside the glass ball, smoke inside the cube, and fog on both sides of the floor.
TEST(MediumScene, BoundariesNameTheMediumOnEitherSide) {
    Scene s = load(mediaScene());
    SceneGeometry geometry = SceneGeometry::build(s);
    MediumBoundaries b = findMediumBoundaries(s, geometry);
    const uint32_t floorTri = 0, cubeTri = 2, ball = geometry.triangleCount();
    EXPECT_EQ(b.inside[floorTri], 0);
    EXPECT_EQ(b.outside[floorTri], 0);
    EXPECT_EQ(b.inside[cubeTri], 2);
    EXPECT_EQ(b.outside[cubeTri], 0);
    EXPECT_EQ(b.inside[ball], 1);
    EXPECT_EQ(b.outside[ball], 0);
    EXPECT_EQ(b.beyond(ball, -0.5f), 1);  // against the normal: inside
    EXPECT_EQ(b.beyond(ball, 0.5f), 0);
    EXPECT_EQ(b.cameraMedium, 0);
    EXPECT_EQ(mediumAt(s, Vec3(0.5f, 0.5f, 0.5f)), 2);
    EXPECT_EQ(mediumAt(s, Vec3(-1.0f, 1.2f, 0.0f)), 1);
    EXPECT_EQ(mediumAt(s, Vec3(3.0f, 1.0f, 0.0f)), 0);

    // Nested: the ball moved inside the smoke cube has smoke outside, milk inside; a camera in
    // the ball is in milk. Without a global medium, space outside is vacuum.
    json j = mediaScene();
    j["shapes"][1]["centre"] = {0.5, 0.5, 0.5};
    j["shapes"][1]["radius"] = 0.25;
    j["camera"]["position"] = {0.5, 0.55, 0.5};
    j.erase("medium");
    Scene nested = load(j);
    SceneGeometry g2 = SceneGeometry::build(nested);
    MediumBoundaries b2 = findMediumBoundaries(nested, g2);
    EXPECT_EQ(b2.inside[g2.triangleCount()], 1);
    EXPECT_EQ(b2.outside[g2.triangleCount()], 2);
    EXPECT_EQ(b2.outside[cubeTri], -1);
    EXPECT_EQ(b2.cameraMedium, 1);
}

TEST(MediumScene, FinalGatherRefusesMedia) {
    Scene s = load(mediaScene());
    try {
        refuseMediaWithoutPathTracer(s, "--method fg");
        ADD_FAILURE() << "a scene with media was accepted by --method fg";
    } catch (const InputError& e) {
        const std::string msg = e.what();
        for (const char* f : {"media.json: medium: expected a scene without participating media for --method fg",
                              "media are rendered by --method progressive, direct and path", "\"fog\" (global)",
                              "\"milk\" in ball", "\"smoke\" in cube"})
            EXPECT_NE(msg.find(f), std::string::npos) << f << " in: " << msg;
    }
    json j = mediaScene();
    j.erase("medium");
    j.erase("media");
    j["shapes"].erase(2);
    j["shapes"][1].erase("medium");
    Scene plain = load(j);
    EXPECT_FALSE(plain.hasMedia());
    EXPECT_NO_THROW(refuseMediaWithoutPathTracer(plain, "--method fg"));
}
