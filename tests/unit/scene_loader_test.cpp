// Scene loaders: the JSON format, the glTF loader and validation. Bad inputs must throw
// InputError whose message names the file and the field; good inputs must give exact numbers.
#include <gtest/gtest.h>
#include "common/optional_feature.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>
#include <unistd.h>

#include "core/error.h"
#include "scene/gltf_loader.h"
#include "scene/json_loader.h"
#include "scene/load_scene.h"
#include "scene/validate.h"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace pcl;

// glTF tests need tinygltf; the lent GPU machine builds without it (PHOTONCL_WITH_GLTF=OFF).
#ifdef PHOTONCL_HAVE_GLTF
#define REQUIRE_GLTF()
#else
#define REQUIRE_GLTF() PCL_REQUIRE_FEATURE(false, "glTF support (tinygltf)")
#endif

namespace {

// A fresh folder per test, removed afterwards.
class SceneLoaderTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("photoncl-scene-test-" + std::to_string(::getpid()) + "-" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string write(const std::string& name, const std::string& text) {
        fs::path p = dir_ / name;
        fs::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << text;
        return p.string();
    }
    std::string write(const std::string& name, const std::vector<unsigned char>& bytes) {
        return write(name, std::string(bytes.begin(), bytes.end()));
    }

    // Loads `path` expecting InputError; every fragment must occur in the message.
    void expectError(const std::string& path, std::initializer_list<std::string> fragments) {
        try {
            loadScene(path);
            ADD_FAILURE() << path << ": expected InputError, loaded fine";
        } catch (const InputError& e) {
            std::string msg = e.what();
            EXPECT_NE(msg.find(path), std::string::npos) << "message lacks the file name: " << msg;
            for (const auto& f : fragments)
                EXPECT_NE(msg.find(f), std::string::npos) << "lacks \"" << f << "\": " << msg;
        }
    }
    // A JSON scene with `patch` merged over a small valid one, then expects an error.
    void expectJsonError(const json& patch, std::initializer_list<std::string> fragments) {
        json scene = baseScene();
        scene.merge_patch(patch);
        expectError(write("bad.json", scene.dump()), fragments);
    }
    Scene loadJson(const json& scene) { return loadScene(write("good.json", scene.dump())); }

    // One white quad lit by a point light, seen by a pinhole camera.
    static json baseScene() {
        return json::parse(R"({
          "camera": {"position": [0, 1, 3], "look_at": [0, 0, 0], "fov": 40, "resolution": [64, 48]},
          "materials": [{"name": "white", "rho_d": [0.5, 0.5, 0.5]}],
          "shapes": [{"type": "quad", "material": "white", "corner": [-1, 0, -1], "edge_u": [0, 0, 2], "edge_v": [2, 0, 0]}],
          "lights": [{"type": "point", "position": [0, 2, 0], "power": [10, 10, 10]}]
        })");
    }

    fs::path dir_;
};

// ---- glTF built in memory: one buffer, base64 data URI (or an external .bin) ---------------------

std::string base64(const std::vector<unsigned char>& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
        uint32_t v = uint32_t(in[i]) << 16 | uint32_t(in[i + 1]) << 8 | in[i + 2];
        out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
    }
    if (i + 1 == in.size()) {
        uint32_t v = uint32_t(in[i]) << 16;
        out += {t[v >> 18], t[(v >> 12) & 63], '=', '='};
    } else if (i + 2 == in.size()) {
        uint32_t v = uint32_t(in[i]) << 16 | uint32_t(in[i + 1]) << 8;
        out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
    }
    return out;
}

// A glTF with one triangle (0,0,0), (1,0,0), (0,1,0) (normal +Z) as mesh 0, material 0, a node
// holding it, a camera node and a point light. Tests edit the returned JSON.
struct GltfDoc {
    json doc;
    std::vector<unsigned char> bin;
};

GltfDoc triangleGltf(bool dataUri = true) {
    GltfDoc g;
    float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    uint16_t idx[4] = {0, 1, 2, 0};  // padded to 4 bytes
    g.bin.resize(sizeof pos + sizeof idx);
    std::memcpy(g.bin.data(), pos, sizeof pos);
    std::memcpy(g.bin.data() + sizeof pos, idx, sizeof idx);
    g.doc = json::parse(R"({
      "asset": {"version": "2.0"},
      "extensionsUsed": ["KHR_lights_punctual"],
      "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "color": [1, 1, 1], "intensity": 683}]}},
      "scene": 0,
      "scenes": [{"nodes": [0, 1, 2]}],
      "nodes": [
        {"name": "tri", "mesh": 0},
        {"name": "cam", "camera": 0, "translation": [0, 0, 5]},
        {"name": "bulb", "translation": [0, 0, 2], "extensions": {"KHR_lights_punctual": {"light": 0}}}
      ],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
      "materials": [{"name": "m", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0, "roughnessFactor": 1}}],
      "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "aspectRatio": 1.5, "znear": 0.1}}],
      "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
        {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}
      ],
      "bufferViews": [
        {"buffer": 0, "byteOffset": 0, "byteLength": 36},
        {"buffer": 0, "byteOffset": 36, "byteLength": 6}
      ],
      "buffers": [{"byteLength": 44}]
    })");
    g.doc["buffers"][0]["uri"] = dataUri ? "data:application/octet-stream;base64," + base64(g.bin) : "tri.bin";
    return g;
}

std::vector<unsigned char> glb(const json& doc, const std::vector<unsigned char>& bin) {
    std::string text = doc.dump();
    while (text.size() % 4) text += ' ';
    std::vector<unsigned char> out;
    auto u32 = [&](uint32_t v) {
        for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
    };
    size_t binPadded = (bin.size() + 3) & ~size_t(3);
    u32(0x46546C67);
    u32(2);
    u32(uint32_t(12 + 8 + text.size() + 8 + binPadded));
    u32(uint32_t(text.size()));
    u32(0x4E4F534A);
    out.insert(out.end(), text.begin(), text.end());
    u32(uint32_t(binPadded));
    u32(0x004E4942);
    out.insert(out.end(), bin.begin(), bin.end());
    while (out.size() % 4) out.push_back(0);
    return out;
}

void expectNear3(Vec3 a, Vec3 b, float tol, const char* what) {
    EXPECT_NEAR(a.x, b.x, tol) << what;
    EXPECT_NEAR(a.y, b.y, tol) << what;
    EXPECT_NEAR(a.z, b.z, tol) << what;
}

}  // namespace

// ================================ Bad input ===================================================

TEST_F(SceneLoaderTest, MissingFile) { expectError((dir_ / "nope.json").string(), {"cannot open"}); }

TEST_F(SceneLoaderTest, UnknownExtension) {
    expectError(write("scene.obj", "x"), {".json, .gltf or .glb", "\".obj\""});
}

TEST_F(SceneLoaderTest, MalformedJson) {
    expectError(write("bad.json", "{\"camera\": {\"fov\": 40,}"), {"expected valid JSON", "line 1"});
}

TEST_F(SceneLoaderTest, TopLevelNotObject) {
    expectError(write("bad.json", "[1, 2]"), {"(top level)", "expected an object"});
}

TEST_F(SceneLoaderTest, DeepNestingFailsCleanly) {
    std::string deep(100000, '[');
    deep += std::string(100000, ']');
    expectError(write("bad.json", deep), {"nested at most", "deeper"});
}

TEST_F(SceneLoaderTest, HugeNumberIsRejected) {
    expectError(write("bad.json", R"({"materials": [{"name": "a", "rho_d": [1e999, 0, 0]}]})"),
                {"expected valid JSON", "1e999"});
}

TEST_F(SceneLoaderTest, UnknownTopLevelKey) {
    expectJsonError({{"lightz", json::array()}}, {"lightz", "unknown key", "camera, materials"});
}

TEST_F(SceneLoaderTest, UnknownMaterialKeyListsAllowedOnes) {
    expectJsonError({{"materials", {{{"name", "white"}, {"rhod", {0.5, 0.5, 0.5}}}}}},
                    {"materials[0].rhod", "unknown key \"rhod\"", "name, rho_d, specular, emission"});
}

TEST_F(SceneLoaderTest, ReflectanceOutOfRange) {
    expectJsonError({{"materials", {{{"name", "white"}, {"rho_d", {1.2, 0, 0}}}}}},
                    {"materials[0].rho_d: expected 3 numbers in [0,1], got [1.2,0,0]"});
}

TEST_F(SceneLoaderTest, ReflectanceWrongType) {
    expectJsonError({{"materials", {{{"name", "white"}, {"rho_d", "grey"}}}}},
                    {"materials[0].rho_d", "3 numbers", "\"grey\""});
}

TEST_F(SceneLoaderTest, ReflectanceWrongLength) {
    expectJsonError({{"materials", {{{"name", "white"}, {"rho_d", {0.5, 0.5}}}}}},
                    {"materials[0].rho_d", "3 numbers", "[0.5,0.5]"});
}

TEST_F(SceneLoaderTest, EnergyConservationEnforced) {
    json m = {
        {"name", "white"}, {"rho_d", {0.6, 0.5, 0.5}}, {"specular", {{"kind", "mirror"}, {"rho_s", {0.5, 0.4, 0.4}}}}};
    expectJsonError({{"materials", {m}}}, {"materials[0]", "rho_d + rho_s <= 1", "1.1"});
}

TEST_F(SceneLoaderTest, UnknownSpecularKind) {
    json m = {{"name", "white"}, {"specular", {{"kind", "velvet"}}}};
    expectJsonError({{"materials", {m}}}, {"materials[0].specular.kind", "mirror, glossy, dielectric", "velvet"});
}

TEST_F(SceneLoaderTest, GlossyNeedsExponent) {
    json m = {{"name", "white"}, {"specular", {{"kind", "glossy"}, {"rho_s", {0.2, 0.2, 0.2}}}}};
    expectJsonError({{"materials", {m}}}, {"materials[0].specular.exponent", "key is missing"});
}

TEST_F(SceneLoaderTest, DuplicateMaterialName) {
    json m = {{"name", "white"}};
    expectJsonError({{"materials", {m, m}}}, {"materials[1].name", "not used by another", "white"});
}

TEST_F(SceneLoaderTest, UnknownMaterialReference) {
    json s = baseScene()["shapes"];
    s[0]["material"] = "chalk";
    expectJsonError({{"shapes", s}}, {"shapes[0].material", "white", "\"chalk\""});
}

TEST_F(SceneLoaderTest, NegativeRadius) {
    json s = {{{"type", "sphere"}, {"material", "white"}, {"centre", {0, 0, 0}}, {"radius", -1}}};
    expectJsonError({{"shapes", s}}, {"shapes[0].radius", "a number > 0", "-1"});
}

TEST_F(SceneLoaderTest, RadiusWrongType) {
    json s = {{{"type", "sphere"}, {"material", "white"}, {"centre", {0, 0, 0}}, {"radius", "big"}}};
    expectJsonError({{"shapes", s}}, {"shapes[0].radius", "\"big\""});
}

TEST_F(SceneLoaderTest, EmissiveSphereRefused) {
    json scene = baseScene();
    scene["materials"].push_back({{"name", "glow"}, {"emission", {1, 1, 1}}});
    scene["shapes"].push_back({{"type", "sphere"}, {"material", "glow"}, {"centre", {0, 0, 0}}, {"radius", 1}});
    expectError(write("bad.json", scene.dump()), {"shapes[1].material", "emitting spheres are not supported"});
}

TEST_F(SceneLoaderTest, UnknownShapeType) {
    json s = {{{"type", "torus"}, {"material", "white"}}};
    expectJsonError({{"shapes", s}}, {"shapes[0].type", "mesh, sphere, quad", "torus"});
}

TEST_F(SceneLoaderTest, MeshIndexOutOfRange) {
    json s = {
        {{"type", "mesh"}, {"material", "white"}, {"positions", {0, 0, 0, 1, 0, 0, 0, 1, 0}}, {"indices", {0, 1, 3}}}};
    expectJsonError({{"shapes", s}}, {"shapes[0].indices[2]", "vertex index in [0, 2]", "3"});
}

TEST_F(SceneLoaderTest, MeshPositionsNotTriples) {
    json s = {{{"type", "mesh"}, {"material", "white"}, {"positions", {0, 0, 0, 1}}, {"indices", {0, 0, 0}}}};
    expectJsonError({{"shapes", s}}, {"shapes[0].positions", "3N finite numbers"});
}

TEST_F(SceneLoaderTest, MissingCamera) {
    json scene = baseScene();
    scene.erase("camera");
    expectError(write("bad.json", scene.dump()), {"camera", "expected a camera"});
}

TEST_F(SceneLoaderTest, CameraLookAtEqualsPosition) {
    expectJsonError({{"camera", {{"look_at", {0, 1, 3}}}}}, {"camera.look_at", "different from the camera position"});
}

TEST_F(SceneLoaderTest, CameraUpParallelToView) {
    expectJsonError({{"camera", {{"position", {0, 3, 0}}, {"up", {0, 1, 0}}}}}, {"camera.up", "not parallel"});
}

TEST_F(SceneLoaderTest, CameraFovOutOfRange) {
    expectJsonError({{"camera", {{"fov", 180}}}}, {"camera.fov", "(0, 180)", "180"});
}

TEST_F(SceneLoaderTest, CameraResolutionNotIntegers) {
    expectJsonError({{"camera", {{"resolution", {64.5, 48}}}}}, {"camera.resolution", "2 integers", "64.5"});
}

TEST_F(SceneLoaderTest, ThinLensNeedsAperture) {
    expectJsonError({{"camera", {{"type", "thin_lens"}}}}, {"camera.aperture_radius", "lens radius > 0", "missing"});
}

TEST_F(SceneLoaderTest, PinholeRefusesLensSettings) {
    expectJsonError({{"camera", {{"aperture_radius", 0.1}}}}, {"camera.aperture_radius", "pinhole", "thin_lens"});
}

TEST_F(SceneLoaderTest, MotionNeedsOpenShutter) {
    json s = baseScene()["shapes"];
    s[0]["motion"] = {1, 0, 0};
    expectJsonError({{"shapes", s}}, {"camera.shutter", "close > open", "[0.000000,0.000000]"});
}

TEST_F(SceneLoaderTest, ZeroPowerLight) {
    json l = {{{"type", "point"}, {"position", {0, 2, 0}}, {"power", {0, 0, 0}}}};
    expectJsonError({{"lights", l}}, {"lights[0].power", "not all zero", "[0,0,0]"});
}

TEST_F(SceneLoaderTest, PowerAndIntensityBoth) {
    json l = {{{"type", "point"}, {"position", {0, 2, 0}}, {"power", {1, 1, 1}}, {"intensity", {1, 1, 1}}}};
    expectJsonError({{"lights", l}}, {"lights[0]", "exactly one of \"power\"", "both"});
}

TEST_F(SceneLoaderTest, PowerAndIntensityNeither) {
    json l = {{{"type", "point"}, {"position", {0, 2, 0}}}};
    expectJsonError({{"lights", l}}, {"lights[0]", "exactly one of \"power\"", "neither"});
}

TEST_F(SceneLoaderTest, NegativeLightPower) {
    json l = {{{"type", "point"}, {"position", {0, 2, 0}}, {"power", {1, -1, 1}}}};
    expectJsonError({{"lights", l}}, {"lights[0].power", ">= 0", "[1,-1,1]"});
}

TEST_F(SceneLoaderTest, SpotInnerWiderThanOuter) {
    json l = {{{"type", "spot"},
               {"position", {0, 2, 0}},
               {"direction", {0, -1, 0}},
               {"power", {1, 1, 1}},
               {"inner_angle", 40},
               {"outer_angle", 30}}};
    expectJsonError({{"lights", l}}, {"lights[0].inner_angle", "[0, outer_angle = 30]", "40"});
}

TEST_F(SceneLoaderTest, DirectionalZeroDirection) {
    json l = {{{"type", "directional"}, {"direction", {0, 0, 0}}, {"irradiance", {1, 1, 1}}}};
    expectJsonError({{"lights", l}}, {"lights[0].direction", "not all zero", "[0,0,0]"});
}

TEST_F(SceneLoaderTest, ZeroAreaLight) {
    json l = {{{"type", "area"},
               {"shape", "quad"},
               {"corner", {0, 1, 0}},
               {"edge_u", {1, 0, 0}},
               {"edge_v", {2, 0, 0}},
               {"power", {1, 1, 1}}}};
    expectJsonError({{"lights", l}}, {"lights[0]", "non-zero, finite area"});
}

TEST_F(SceneLoaderTest, NoLightAndNoEmitter) {
    json scene = baseScene();
    scene["lights"] = json::array();
    expectError(write("bad.json", scene.dump()),
                {"lights", "at least one light, emissive surface or environment", "none"});
}

TEST_F(SceneLoaderTest, IncludeLeavingFolderRefused) {
    write("secret.gltf", "{}");
    fs::create_directories(dir_ / "sub");
    json scene = baseScene();
    scene["include"] = "../secret.gltf";
    expectError(write("sub/bad.json", scene.dump()), {"include", "inside the scene's folder", "leaves the folder"});
}

TEST_F(SceneLoaderTest, IncludeAbsolutePathRefused) {
    json scene = baseScene();
    scene["include"] = "/etc/passwd.gltf";
    expectError(write("bad.json", scene.dump()), {"include", "inside the scene's folder", "absolute"});
}

TEST_F(SceneLoaderTest, MeshGltfSourceMustBeGltf) {
    json s = {{{"type", "mesh"}, {"gltf", "model.obj"}}};
    expectJsonError({{"shapes", s}}, {"shapes[0].gltf", ".gltf or .glb", "model.obj"});
}

TEST_F(SceneLoaderTest, TransformUnknownKey) {
    json s = {{{"type", "mesh"},
               {"material", "white"},
               {"positions", {0, 0, 0, 1, 0, 0, 0, 1, 0}},
               {"indices", {0, 1, 2}},
               {"transform", {{"shear", 1}}}}};
    expectJsonError({{"shapes", s}}, {"shapes[0].transform.shear", "translate, rotate, scale, matrix"});
}

TEST_F(SceneLoaderTest, GltfMissingBuffer) {
    REQUIRE_GLTF();
    GltfDoc g = triangleGltf(false);  // refers to tri.bin, not written
    expectError(write("scene.gltf", g.doc.dump()), {"buffers[0].uri", "existing buffer file", "tri.bin"});
}

TEST_F(SceneLoaderTest, GltfUnsupportedRequiredExtension) {
    REQUIRE_GLTF();
    GltfDoc g = triangleGltf();
    g.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    expectError(write("scene.gltf", g.doc.dump()),
                {"extensionsRequired[0]", "supported extension", "KHR_draco_mesh_compression"});
}

TEST_F(SceneLoaderTest, GltfBufferUriLeavingFolder) {
    REQUIRE_GLTF();
    GltfDoc g = triangleGltf(false);
    write("tri.bin", g.bin);
    g.doc["buffers"][0]["uri"] = "%2e%2e/tri.bin";  // percent-encoded ".."
    fs::create_directories(dir_ / "sub");
    expectError(write("sub/scene.gltf", g.doc.dump()),
                {"buffers[0].uri", "inside the scene's folder", "leaves the folder"});
}

TEST_F(SceneLoaderTest, GltfDeepNesting) {
    REQUIRE_GLTF();
    std::string deep = "{\"asset\": {\"version\": \"2.0\"}, \"extras\": " + std::string(100000, '[') +
                       std::string(100000, ']') + "}";
    expectError(write("scene.gltf", deep), {"nested at most"});
}

TEST_F(SceneLoaderTest, GltfWrongVersion) {
    REQUIRE_GLTF();
    GltfDoc g = triangleGltf();
    g.doc["asset"]["version"] = "1.0";
    expectError(write("scene.gltf", g.doc.dump()), {"asset.version", "\"2.0\"", "\"1.0\""});
}

TEST_F(SceneLoaderTest, GltfAccessorOutsideBuffer) {
    REQUIRE_GLTF();
    GltfDoc g = triangleGltf();
    g.doc["accessors"][0]["count"] = 4;
    expectError(write("scene.gltf", g.doc.dump()), {"accessors[0]", "inside bufferView 0"});
}

TEST_F(SceneLoaderTest, GltfIndexBeyondVertices) {
    REQUIRE_GLTF();
    GltfDoc g = triangleGltf();
    g.doc["accessors"][0]["count"] = 2;
    g.doc["bufferViews"][0]["byteLength"] = 36;
    expectError(write("scene.gltf", g.doc.dump()), {"meshes[0].primitives[0].indices", "vertex indices below 2", "2"});
}

TEST_F(SceneLoaderTest, GltfNodeCycle) {
    REQUIRE_GLTF();
    GltfDoc g = triangleGltf();
    g.doc["nodes"][0]["children"] = {0};
    expectError(write("scene.gltf", g.doc.dump()), {"nodes[0]", "glTF nodes form a tree", "reached twice"});
}

// glTF node matrices are column-major: elements 3, 7, 11 and 15 are the last row, which must be
// 0 0 0 1 (an affine transform). Each element off its value is refused, naming the node.
TEST_F(SceneLoaderTest, GltfNodeMatrixNotAffine) {
    REQUIRE_GLTF();
    for (int element : {3, 7, 11, 15}) {
        GltfDoc g = triangleGltf();
        json m = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        m[size_t(element)] = element == 15 ? 2.0 : 0.5;
        g.doc["nodes"][0]["name"] = "tilted";
        g.doc["nodes"][0]["matrix"] = m;
        const std::string row = element == 3    ? "last row 0.5 0 0 1"
                                : element == 7  ? "last row 0 0.5 0 1"
                                : element == 11 ? "last row 0 0 0.5 1"
                                                : "last row 0 0 0 2";
        expectError(write("scene.gltf", g.doc.dump()),
                    {"scene.gltf", "nodes[0] (\"tilted\").matrix", "an affine matrix", "last row 0 0 0 1", row});
    }
    // The translation column (12, 13, 14) is fine.
    GltfDoc g = triangleGltf();
    g.doc["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.5, 0.5, 0.5, 1};
    EXPECT_NO_THROW(loadScene(write("scene.gltf", g.doc.dump())));
}

TEST_F(SceneLoaderTest, GltfBaseColorOutOfRange) {
    REQUIRE_GLTF();
    GltfDoc g = triangleGltf();
    g.doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {1.5, 0, 0, 1};
    expectError(write("scene.gltf", g.doc.dump()),
                {"materials[0].pbrMetallicRoughness.baseColorFactor", "[0, 1]", "1.5"});
}

TEST_F(SceneLoaderTest, GlbTruncated) {
    REQUIRE_GLTF();
    GltfDoc g = triangleGltf();
    std::vector<unsigned char> bytes = glb(g.doc, g.bin);
    bytes.resize(bytes.size() - 30);
    expectError(write("scene.glb", bytes), {"header.length", "at most the file size"});
}

TEST_F(SceneLoaderTest, GltfWithoutCamera) {
    REQUIRE_GLTF();
    GltfDoc g = triangleGltf();
    g.doc["scenes"][0]["nodes"] = {0, 2};
    expectError(write("scene.gltf", g.doc.dump()), {"cameras", "a camera on some node", "none"});
}

#ifndef PHOTONCL_HAVE_GLTF
TEST_F(SceneLoaderTest, WithoutGltfSupportGltfIsRefusedClearly) {
    expectError(write("scene.gltf", "{}"), {"built without glTF support"});
    json scene = baseScene();
    scene["include"] = "x.gltf";
    expectError(write("bad.json", scene.dump()), {"include", "built without glTF support"});
}
#endif

// ================================ Good input ==================================================

TEST_F(SceneLoaderTest, PointLightPowerToIntensity) {
    json scene = baseScene();
    scene["lights"][0]["power"] = {4 * kPi, 8 * kPi, 2 * kPi};
    Scene s = loadJson(scene);
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].type, LightType::Point);
    expectNear3(s.lights[0].intensity, {1, 2, 0.5f}, 1e-6f, "I = Φ/4π");
}

TEST_F(SceneLoaderTest, SpotLightPowerToIntensity) {
    json scene = baseScene();
    scene["lights"] = {{{"type", "spot"},
                        {"position", {0, 2, 0}},
                        {"direction", {0, -2, 0}},
                        {"power", {3, 3, 3}},
                        {"inner_angle", 20},
                        {"outer_angle", 30}}};
    Scene s = loadJson(scene);
    const Light& l = s.lights[0];
    double ci = std::cos(20 * M_PI / 180), co = std::cos(30 * M_PI / 180);
    double expected = 3.0 / (2 * M_PI * ((1 - ci) + (ci - co) / 2));
    EXPECT_NEAR(l.intensity.x, expected, 1e-5 * expected);
    EXPECT_NEAR(l.cosInner, ci, 1e-6);
    EXPECT_NEAR(l.cosOuter, co, 1e-6);
    expectNear3(l.direction, {0, -1, 0}, 1e-6f, "normalised direction");
}

TEST_F(SceneLoaderTest, SpotLightIntensityKeptAsGiven) {
    json scene = baseScene();
    scene["lights"] = {{{"type", "spot"},
                        {"position", {0, 2, 0}},
                        {"direction", {0, -1, 0}},
                        {"intensity", {2, 3, 4}},
                        {"outer_angle", 45}}};
    Scene s = loadJson(scene);
    expectNear3(s.lights[0].intensity, {2, 3, 4}, 0, "intensity");
    EXPECT_FLOAT_EQ(s.lights[0].cosInner, 1.0f);
}

TEST_F(SceneLoaderTest, AreaQuadLightRadianceFromPower) {
    json scene = baseScene();
    // 0.5 x 0.4 quad facing down: A = 0.2, L = Φ/(πA).
    scene["lights"] = {{{"type", "area"},
                        {"name", "lamp"},
                        {"shape", "quad"},
                        {"corner", {0, 2, 0}},
                        {"edge_u", {0.5, 0, 0}},
                        {"edge_v", {0, 0, 0.4}},
                        {"power", {1, 2, 3}}}};
    Scene s = loadJson(scene);
    ASSERT_EQ(s.lights.size(), 1u);
    const Light& l = s.lights[0];
    ASSERT_EQ(l.type, LightType::Area);
    const TriangleMesh& m = s.meshes[size_t(l.mesh)];
    EXPECT_EQ(m.triangleCount(), 2u);
    Vec3 e = s.materials[size_t(m.material)].emission;
    expectNear3(e, Vec3(1, 2, 3) / (kPi * 0.2f), 1e-5f, "L = Φ/(πA)");
    EXPECT_EQ(s.materials[size_t(m.material)].rhoD, Vec3(0.0f));
    // Geometric normal cross(u, v) = (0.5,0,0) x (0,0,0.4) points down.
    Vec3 n = cross(m.positions[m.indices[1]] - m.positions[m.indices[0]],
                   m.positions[m.indices[2]] - m.positions[m.indices[0]]);
    expectNear3(normalize(n), {0, -1, 0}, 1e-6f, "area light faces -y");
}

TEST_F(SceneLoaderTest, AreaTriangleLightByRadiance) {
    json scene = baseScene();
    scene["lights"] = {{{"type", "area"},
                        {"shape", "triangle"},
                        {"vertices", {{0, 2, 0}, {0, 2, 1}, {1, 2, 0}}},
                        {"radiance", {5, 5, 5}}}};
    Scene s = loadJson(scene);
    const TriangleMesh& m = s.meshes[size_t(s.lights[0].mesh)];
    expectNear3(s.materials[size_t(m.material)].emission, {5, 5, 5}, 0, "radiance as given");
    EXPECT_EQ(m.triangleCount(), 1u);
}

TEST_F(SceneLoaderTest, QuadGeometryNormalAndArea) {
    json scene = baseScene();
    scene["shapes"][0] = {
        {"type", "quad"}, {"material", "white"}, {"corner", {1, 2, 3}}, {"edge_u", {2, 0, 0}}, {"edge_v", {0, 3, 0}}};
    Scene s = loadJson(scene);
    const TriangleMesh& m = s.meshes[0];
    ASSERT_EQ(m.triangleCount(), 2u);
    float area = 0;
    for (size_t t = 0; t < 2; ++t) {
        Vec3 p0 = m.positions[m.indices[3 * t]], p1 = m.positions[m.indices[3 * t + 1]],
             p2 = m.positions[m.indices[3 * t + 2]];
        Vec3 n = cross(p1 - p0, p2 - p0);
        area += 0.5f * length(n);
        expectNear3(normalize(n), {0, 0, 1}, 1e-6f, "normal = cross(u, v)");
    }
    EXPECT_NEAR(area, 6.0f, 1e-5f);
    expectNear3(m.positions[2], {3, 5, 3}, 0, "corner + u + v");
}

TEST_F(SceneLoaderTest, EmissiveQuadBecomesAreaLight) {
    json scene = baseScene();
    scene["materials"].push_back({{"name", "glow"}, {"emission", {2, 2, 2}}});
    scene["shapes"].push_back(
        {{"type", "quad"}, {"material", "glow"}, {"corner", {0, 1, 0}}, {"edge_u", {1, 0, 0}}, {"edge_v", {0, 0, 1}}});
    scene["lights"] = json::array();  // the emitter alone lights the scene
    Scene s = loadJson(scene);
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].type, LightType::Area);
    EXPECT_EQ(s.lights[0].mesh, 1);
}

TEST_F(SceneLoaderTest, DegenerateTrianglesDroppedAndCounted) {
    json scene = baseScene();
    scene["shapes"].push_back({{"type", "mesh"},
                               {"material", "white"},
                               {"positions", {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0}},
                               {"indices", {0, 1, 2, 0, 1, 3, 1, 1, 2}}});  // 2nd collinear, 3rd repeats a vertex
    Scene s = loadJson(scene);
    EXPECT_EQ(s.droppedDegenerateTriangles, 2u);
    EXPECT_EQ(s.meshes[1].triangleCount(), 1u);
}

TEST_F(SceneLoaderTest, InlineMeshTransformAndMirrorKeepsFrontSide) {
    json scene = baseScene();
    json mesh = {{"type", "mesh"},
                 {"material", "white"},
                 {"positions", {0, 0, 0, 1, 0, 0, 0, 1, 0}},
                 {"indices", {0, 1, 2}},
                 {"normals", {0, 0, 1, 0, 0, 1, 0, 0, 1}}};
    mesh["transform"] = {{"translate", {1, 2, 3}}, {"rotate", {{"axis", {0, 0, 1}}, {"degrees", 90}}}, {"scale", 2}};
    scene["shapes"].push_back(mesh);
    mesh["transform"] = {{"scale", {1, 1, -1}}};  // a mirror: winding must flip to keep the normal side
    scene["shapes"].push_back(mesh);
    Scene s = loadJson(scene);
    const TriangleMesh& a = s.meshes[1];
    // T·R·S: (1,0,0) → scale 2 → (2,0,0) → rotate 90° about z → (0,2,0) → translate → (1,4,3).
    expectNear3(a.positions[1], {1, 4, 3}, 1e-5f, "T·R·S order");
    expectNear3(a.positions[2], {-1, 2, 3}, 1e-5f, "T·R·S order");
    expectNear3(a.normals[0], {0, 0, 1}, 1e-6f, "normal rotated about its own axis");
    const TriangleMesh& b = s.meshes[2];
    expectNear3(b.normals[0], {0, 0, -1}, 1e-6f, "mirrored normal");
    Vec3 g = cross(b.positions[b.indices[1]] - b.positions[b.indices[0]],
                   b.positions[b.indices[2]] - b.positions[b.indices[0]]);
    EXPECT_GT(dot(g, b.normals[0]), 0) << "geometric normal on the shading normal's side after mirroring";
}

TEST_F(SceneLoaderTest, MaterialsAndCameraRead) {
    json scene = baseScene();
    scene["materials"].push_back({{"name", "glass"}, {"specular", {{"kind", "dielectric"}, {"ior", 1.33}}}});
    scene["materials"].push_back({{"name", "shiny"},
                                  {"rho_d", {0.2, 0.2, 0.2}},
                                  {"specular", {{"kind", "glossy"}, {"rho_s", {0.3, 0.3, 0.3}}, {"exponent", 80}}}});
    scene["camera"] = {{"type", "thin_lens"},     {"position", {0, 0, 4}},   {"look_at", {0, 0, 0}}, {"fov", 30},
                       {"resolution", {100, 50}}, {"aperture_radius", 0.05}, {"shutter", {0.1, 0.3}}};
    Scene s = loadJson(scene);
    EXPECT_EQ(s.materials[1].specular, SpecularKind::Dielectric);
    EXPECT_FLOAT_EQ(s.materials[1].ior, 1.33f);
    expectNear3(s.materials[1].rhoS, {1, 1, 1}, 0, "dielectric default rho_s");
    EXPECT_EQ(s.materials[2].specular, SpecularKind::Glossy);
    EXPECT_FLOAT_EQ(s.materials[2].phongExponent, 80.0f);
    EXPECT_EQ(s.camera.model, CameraModel::ThinLens);
    EXPECT_FLOAT_EQ(s.camera.focusDistance, 4.0f);  // defaults to the distance to look_at
    EXPECT_EQ(s.camera.width, 100);
    EXPECT_EQ(s.camera.height, 50);
    EXPECT_FLOAT_EQ(s.camera.shutterOpen, 0.1f);
    EXPECT_FLOAT_EQ(s.camera.shutterClose, 0.3f);
}

TEST_F(SceneLoaderTest, GltfNodeHierarchyTransforms) {
    REQUIRE_GLTF();
    GltfDoc g = triangleGltf();
    // Parent: translate (1,2,3); child: rotate 90° about +Y then scale 2. Column-major matrix on a
    // third level: translate (0,0,-1).
    g.doc["nodes"][0] = {{"name", "parent"}, {"translation", {1, 2, 3}}, {"children", {3}}};
    double s = std::sqrt(0.5);
    g.doc["nodes"].push_back({{"name", "child"}, {"rotation", {0, s, 0, s}}, {"scale", {2, 2, 2}}, {"children", {4}}});
    g.doc["nodes"].push_back(
        {{"name", "leaf"}, {"mesh", 0}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -1, 1}}});
    Scene sc = loadScene(write("scene.gltf", g.doc.dump()));
    ASSERT_EQ(sc.meshes.size(), 1u);
    const TriangleMesh& m = sc.meshes[0];
    // p=(1,0,0): leaf → (1,0,-1); rotate 90° about y: (x,z) → (z,-x) = (-1,0,-1); ×2 → (-2,0,-2); +T → (-1,2,1).
    expectNear3(m.positions[1], {-1, 2, 1}, 1e-5f, "vertex 1");
    // p=(0,0,0): leaf → (0,0,-1) → rot (-1,0,0) → ×2 (-2,0,0) → (-1,2,3).
    expectNear3(m.positions[0], {-1, 2, 3}, 1e-5f, "vertex 0");
}

TEST_F(SceneLoaderTest, GltfMaterialMapping) {
    REQUIRE_GLTF();
    GltfDoc g = triangleGltf();
    auto& mats = g.doc["materials"];
    mats = json::array();
    auto pbr = [](std::vector<double> base, double metallic, double rough) {
        return json{{"baseColorFactor", base}, {"metallicFactor", metallic}, {"roughnessFactor", rough}};
    };
    mats.push_back({{"name", "plastic"}, {"pbrMetallicRoughness", pbr({0.5, 0.5, 0.5, 1}, 0, 1)}});
    mats.push_back({{"name", "metal"}, {"pbrMetallicRoughness", pbr({0.8, 0.6, 0.4, 1}, 1, 0.35)}});
    mats.push_back({{"name", "chrome"}, {"pbrMetallicRoughness", pbr({0.9, 0.9, 0.9, 1}, 1, 0.02)}});
    mats.push_back(
        {{"name", "glass"},
         {"pbrMetallicRoughness", pbr({1, 1, 1, 1}, 0, 0)},
         {"extensions",
          {{"KHR_materials_transmission", {{"transmissionFactor", 1}}}, {"KHR_materials_ior", {{"ior", 1.7}}}}}});
    mats.push_back({{"name", "lamp"},
                    {"pbrMetallicRoughness", pbr({0, 0, 0, 1}, 0, 1)},
                    {"emissiveFactor", {1, 0.5, 0.25}},
                    {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 8}}}}}});
    json node = g.doc["nodes"][0];
    g.doc["nodes"] = json::array();
    g.doc["meshes"] = json::array();
    for (int i = 0; i < 5; ++i) {
        json prim = {{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", i}};
        g.doc["meshes"].push_back({{"primitives", json::array({prim})}});
        g.doc["nodes"].push_back({{"mesh", i}, {"translation", {0, 0, -i}}});
    }
    g.doc["nodes"].push_back({{"camera", 0}, {"translation", {0, 0, 5}}});
    g.doc["scenes"][0]["nodes"] = {0, 1, 2, 3, 4, 5};
    Scene s = loadScene(write("scene.gltf", g.doc.dump()));
    ASSERT_EQ(s.meshes.size(), 5u);
    auto mat = [&](int i) { return s.materials[size_t(s.meshes[size_t(i)].material)]; };
    // Rough dielectric: lobe folded into diffuse: ρd = 0.96·0.5 + 0.04.
    EXPECT_EQ(mat(0).specular, SpecularKind::None);
    expectNear3(mat(0).rhoD, Vec3(0.52f), 1e-6f, "plastic rho_d");
    // Metal, roughness 0.35: α = 0.1225, n = 1/(2α²) - 1/2.
    EXPECT_EQ(mat(1).specular, SpecularKind::Glossy);
    double a = 0.35 * 0.35;
    EXPECT_NEAR(mat(1).phongExponent, 0.5 / (a * a) - 0.5, 1e-3);
    expectNear3(mat(1).rhoS, {0.8f, 0.6f, 0.4f}, 1e-6f, "metal rho_s = base");
    expectNear3(mat(1).rhoD, Vec3(0.0f), 0, "metal rho_d");
    EXPECT_EQ(mat(2).specular, SpecularKind::Mirror);
    EXPECT_EQ(mat(3).specular, SpecularKind::Dielectric);
    EXPECT_FLOAT_EQ(mat(3).ior, 1.7f);
    expectNear3(mat(3).rhoS, Vec3(1.0f), 0, "glass rho_s");
    expectNear3(mat(4).emission, {8, 4, 2}, 1e-6f, "emissive · strength");
    // The emissive mesh got an area light; plus the glTF point light.
    int areas = 0;
    for (const auto& l : s.lights) areas += l.type == LightType::Area && l.mesh == 4;
    EXPECT_EQ(areas, 1);
}

TEST_F(SceneLoaderTest, GltfPunctualLightsAndCamera) {
    REQUIRE_GLTF();
    GltfDoc g = triangleGltf();
    g.doc["extensions"]["KHR_lights_punctual"]["lights"].push_back(
        {{"type", "spot"}, {"intensity", 1366}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}});
    g.doc["extensions"]["KHR_lights_punctual"]["lights"].push_back(
        {{"type", "directional"}, {"color", {1, 0.5, 0}}, {"intensity", 6.83}});
    double s = std::sqrt(0.5);
    // Spot at (0,3,0) rotated -90° about X: its -Z axis points down.
    g.doc["nodes"].push_back({{"translation", {0, 3, 0}},
                              {"rotation", {-s, 0, 0, s}},
                              {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
    g.doc["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
    g.doc["scenes"][0]["nodes"] = {0, 1, 2, 3, 4};
    Scene sc = loadScene(write("scene.gltf", g.doc.dump()));
    ASSERT_EQ(sc.lights.size(), 3u);
    EXPECT_EQ(sc.lights[0].type, LightType::Point);
    expectNear3(sc.lights[0].intensity, Vec3(1.0f), 1e-6f, "683 cd = 1 W/sr");
    expectNear3(sc.lights[0].position, {0, 0, 2}, 1e-6f, "point position");
    EXPECT_EQ(sc.lights[1].type, LightType::Spot);
    expectNear3(sc.lights[1].intensity, Vec3(2.0f), 1e-6f, "spot W/sr");
    expectNear3(sc.lights[1].direction, {0, -1, 0}, 1e-6f, "spot axis");
    EXPECT_NEAR(sc.lights[1].cosInner, std::cos(0.2), 1e-6);
    EXPECT_NEAR(sc.lights[1].cosOuter, std::cos(0.5), 1e-6);
    EXPECT_EQ(sc.lights[2].type, LightType::Directional);
    expectNear3(sc.lights[2].irradiance, {0.01f, 0.005f, 0}, 1e-7f, "lux / 683");
    expectNear3(sc.lights[2].direction, {0, 0, -1}, 1e-6f, "directional along -Z");
    // Camera at (0,0,5) looking down -Z; yfov 0.8 rad; 256 rows, aspect 1.5.
    expectNear3(sc.camera.position, {0, 0, 5}, 1e-6f, "camera position");
    expectNear3(sc.camera.lookAt, {0, 0, 4}, 1e-6f, "camera look_at");
    EXPECT_NEAR(sc.camera.vfovDegrees, 0.8 * 180 / M_PI, 1e-4);
    EXPECT_EQ(sc.camera.height, 256);
    EXPECT_EQ(sc.camera.width, 384);
}

TEST_F(SceneLoaderTest, GlbAndExternalBufferLoadLikeEmbedded) {
    REQUIRE_GLTF();
    GltfDoc embedded = triangleGltf();
    Scene a = loadScene(write("a.gltf", embedded.doc.dump()));
    GltfDoc external = triangleGltf(false);
    write("tri.bin", external.bin);
    Scene b = loadScene(write("b.gltf", external.doc.dump()));
    GltfDoc binary = triangleGltf();
    binary.doc["buffers"][0].erase("uri");
    Scene c = loadScene(write("c.glb", glb(binary.doc, binary.bin)));
    for (const Scene* s : {&b, &c}) {
        ASSERT_EQ(s->meshes.size(), 1u);
        EXPECT_EQ(s->meshes[0].indices, a.meshes[0].indices);
        for (size_t i = 0; i < 3; ++i)
            expectNear3(s->meshes[0].positions[i], a.meshes[0].positions[i], 0, "same vertex");
    }
}

TEST_F(SceneLoaderTest, JsonIncludesGltf) {
    REQUIRE_GLTF();
    GltfDoc g = triangleGltf();
    write("models/tri.gltf", g.doc.dump());
    json scene = baseScene();
    scene.erase("camera");  // taken from the included file
    scene["include"] = {{{"file", "models/tri.gltf"}, {"transform", {{"translate", {10, 0, 0}}}}}};
    scene["shapes"].push_back(
        {{"type", "mesh"}, {"gltf", "models/tri.gltf"}, {"material", "white"}, {"transform", {{"scale", 3}}}});
    Scene s = loadJson(scene);
    // base quad + the mesh shape (override material, scaled) + the include (own material, moved).
    ASSERT_EQ(s.meshes.size(), 3u);
    expectNear3(s.meshes[1].positions[1], {3, 0, 0}, 1e-6f, "mesh source scaled");
    EXPECT_EQ(s.meshes[1].material, 0);
    expectNear3(s.meshes[2].positions[1], {11, 0, 0}, 1e-6f, "include translated");
    EXPECT_NE(s.meshes[2].material, 0);
    // The include brought its point light (moved too) and camera (also under the include transform).
    ASSERT_EQ(s.lights.size(), 2u);
    expectNear3(s.lights[1].position, {10, 0, 2}, 1e-6f, "included light moved");
    expectNear3(s.camera.position, {10, 0, 5}, 1e-6f, "included camera");
}

TEST_F(SceneLoaderTest, MotionNeedsShutterButLoadsWithIt) {
    json scene = baseScene();
    scene["shapes"].push_back(
        {{"type", "sphere"}, {"material", "white"}, {"centre", {0, 1, 0}}, {"radius", 0.5}, {"motion", {1, 0, 0}}});
    scene["camera"]["shutter"] = {0, 0.5};
    Scene s = loadJson(scene);
    EXPECT_TRUE(s.hasMotion());
    expectNear3(s.spheres[0].motion, {1, 0, 0}, 0, "sphere motion");
}

// Every shipped scene loads and is what its name says.
TEST_F(SceneLoaderTest, ShippedScenesLoad) {
    const std::string dir = std::string(PHOTONCL_SOURCE_DIR) + "/scenes/";
    struct Expect {
        const char* file;
        size_t lights;
        LightType firstLight;
        size_t spheres;
    };
    for (Expect e :
         {Expect{"cornell-box.json", 1, LightType::Area, 0}, Expect{"cornell-spheres.json", 1, LightType::Area, 2},
          Expect{"cornell-spheres-point.json", 1, LightType::Point, 2},
          Expect{"cornell-glossy.json", 1, LightType::Area, 0}, Expect{"motion-dof.json", 2, LightType::Area, 5},
          Expect{"gltf-room.gltf", 2, LightType::Point, 0}}) {
        SCOPED_TRACE(e.file);
#ifndef PHOTONCL_HAVE_GLTF
        if (std::string(e.file).find(".gltf") != std::string::npos) continue;
#endif
        Scene s = loadScene(dir + e.file);
        EXPECT_EQ(s.lights.size(), e.lights);
        EXPECT_EQ(s.spheres.size(), e.spheres);
        bool found = false;
        for (const auto& l : s.lights) found = found || l.type == e.firstLight;
        EXPECT_TRUE(found);
        EXPECT_EQ(s.droppedDegenerateTriangles, 0u);
        EXPECT_GT(s.triangleCount(), 0u);
        for (const auto& m : s.materials) {
            EXPECT_LE(maxComponent(m.rhoD + m.rhoS), 1.0f) << m.name;
            if (m.specular == SpecularKind::None || m.specular == SpecularKind::Glossy) {
                EXPECT_LE(maxComponent(m.rhoD), 0.8f) << m.name;
            }
        }
    }
    Scene spheres = loadScene(dir + "cornell-spheres.json");
    Scene box = loadScene(dir + "cornell-box.json");
    // The lamp is given by radiance in one file and by power in the other: same radiance.
    Vec3 l1 = box.materials[size_t(box.meshes[size_t(box.lights[0].mesh)].material)].emission;
    Vec3 l2 = spheres.materials[size_t(spheres.meshes[size_t(spheres.lights[0].mesh)].material)].emission;
    expectNear3(l1, l2, 1e-3f, "lamp radiance from power");
    EXPECT_EQ(box.camera.width, 256);
    Scene dof = loadScene(dir + "motion-dof.json");
    EXPECT_EQ(dof.camera.model, CameraModel::ThinLens);
    EXPECT_TRUE(dof.hasMotion());
#ifdef PHOTONCL_HAVE_GLTF
    Scene room = loadScene(dir + "gltf-room.gltf");
    int mirrors = 0, glossy = 0, glass = 0;
    for (const auto& m : room.materials) {
        mirrors += m.specular == SpecularKind::Mirror;
        glossy += m.specular == SpecularKind::Glossy;
        glass += m.specular == SpecularKind::Dielectric;
    }
    EXPECT_EQ(mirrors, 1);
    EXPECT_EQ(glossy, 1);
    EXPECT_EQ(glass, 1);
#endif
}

// The stress generator's output (at a small grid) loads through the JSON include.
TEST_F(SceneLoaderTest, StressScriptOutputLoads) {
    REQUIRE_GLTF();
    std::string cmd = "python3 " + std::string(PHOTONCL_SOURCE_DIR) + "/scripts/gen_stress_scene.py " + dir_.string() +
                      " --grid 21 > /dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    Scene s = loadScene((dir_ / "stress.json").string());
    EXPECT_EQ(s.triangleCount(), 2u * 20 * 20 + 2);  // the terrain and the 2-triangle sky panel
}

// The fuzz seed corpus, run the way the harnesses run it: each must give a Scene or an
// InputError, nothing else. (The regressions have their own, stricter test:
// fuzz_regressions_test.cpp.)
TEST_F(SceneLoaderTest, FuzzCorpusGivesSceneOrInputError) {
    const fs::path root = fs::path(PHOTONCL_SOURCE_DIR) / "tests" / "fuzz";
    size_t files = 0;
    for (const char* kind : {"json", "gltf"}) {
#ifndef PHOTONCL_HAVE_GLTF
        if (std::string(kind) == "gltf") continue;
#endif
        {
            const fs::path dir = root / "corpus" / kind;
            ASSERT_TRUE(fs::is_directory(dir)) << dir << " is missing";
            for (const auto& entry : fs::directory_iterator(dir)) {
                std::ifstream in(entry.path(), std::ios::binary);
                std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
                SCOPED_TRACE(entry.path().string());
                ++files;
                try {
                    Scene scene;
                    if (std::string(kind) == "json") {
                        scene = parseJsonScene(text, "photoncl-fuzz-no-such-dir/scene.json");
                    } else {
#ifdef PHOTONCL_HAVE_GLTF
                        scene.path = "photoncl-fuzz-no-such-dir/scene.gltf";
                        GltfImportResult r = importGltfFromMemory(scene,
                                                                  std::vector<unsigned char>(text.begin(), text.end()),
                                                                  scene.path, GltfImportOptions{});
                        if (r.hasCamera) scene.camera = r.camera;
#endif
                    }
                    validateScene(scene);
                } catch (const InputError&) {
                } catch (const std::exception& e) {
                    ADD_FAILURE() << "not an InputError: " << e.what();
                }
            }
        }
    }
    EXPECT_GE(files, 5u);
}
