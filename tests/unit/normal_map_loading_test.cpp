// Normal maps as the loaders read them (scenes/README.md, "Normal maps" and the glTF table):
// glTF material.normalTexture (index, texCoord, scale, KHR_texture_transform, sampler) read with
// linear texels (not sRGB: they are vectors), the TANGENT attribute kept (and moved by the node's
// transform, w flipped by a mirror), tangents generated for a mesh without them; the JSON
// material field "normal_map" with the fields of every JSON texture plus "normal_scale"; bad
// normal maps refused with the usual message (file, field, what was found, what was expected).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>
#include <unistd.h>

#include "common/optional_feature.h"
#include "common/scene_folder_test.h"
#include "core/error.h"
#include "image/image_io.h"
#include "scene/load_scene.h"
#include "scene/texture_image.h"

using namespace pcl;
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

class NormalMapLoadingTest : public test::SceneFolderTest {
protected:
    void SetUp() override {
        PCL_REQUIRE_FEATURE(haveOpenImageIO(), "OpenImageIO (PNG normal maps)");
        makeFolder("photoncl-normal-map");
        // The unit quad in z = 0 facing +z, TEXCOORD_0 upright (v down), TANGENT +x with w = 1.
        const float pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
        const float uv0[8] = {0, 1, 1, 1, 1, 0, 0, 0};
        const float tan[16] = {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1};
        const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
        std::string bin(sizeof pos + sizeof uv0 + sizeof tan + sizeof idx, '\0');
        std::memcpy(&bin[0], pos, sizeof pos);
        std::memcpy(&bin[48], uv0, sizeof uv0);
        std::memcpy(&bin[80], tan, sizeof tan);
        std::memcpy(&bin[144], idx, sizeof idx);
        std::ofstream(dir_ / "quad.bin", std::ios::binary) << bin;
        // A 1 × 1 PNG whose code values are (0.5, 0.5, 1) after sRGB encoding of linear kGrey.
        Image img(1, 1);
        img.set(0, 0, Vec3(kGrey, kGrey, 1.0f));
        ASSERT_TRUE(writeSrgbPng((dir_ / "normal.png").string(), img));
        Image two(2, 2);  // 2 channels are refused
        ASSERT_TRUE(writeSrgbPng((dir_ / "flat.png").string(), two));
    }
    static constexpr float kGrey = 0.2158605f;  // linear of sRGB code 128

    static json gltf() {
        return json::parse(R"({
          "asset": {"version": "2.0"},
          "extensionsUsed": ["KHR_lights_punctual", "KHR_texture_transform"],
          "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 683}]}},
          "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
          "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.5, 0.5, 3]},
                    {"translation": [0.5, 0.5, 2], "extensions": {"KHR_lights_punctual": {"light": 0}}}],
          "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.1}}],
          "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1, "TANGENT": 2}, "indices": 3, "material": 0}]}],
          "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0},
                         "normalTexture": {"index": 0, "scale": 0.5,
                                           "extensions": {"KHR_texture_transform": {"scale": [2, 2]}}}}],
          "textures": [{"source": 0, "sampler": 0}],
          "samplers": [{"wrapS": 33648, "wrapT": 10497}],
          "images": [{"uri": "normal.png"}],
          "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC4"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}
          ],
          "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 64},
            {"buffer": 0, "byteOffset": 144, "byteLength": 12}
          ],
          "buffers": [{"uri": "quad.bin", "byteLength": 156}]
        })");
    }
    static json jsonScene(const json& normalMap) {
        json s = json::parse(R"({
          "camera": {"position": [0, 3, 0.01], "look_at": [0, 0, 0], "fov": 40, "resolution": [16, 16]},
          "materials": [{"name": "bumpy", "rho_d": [0.5, 0.5, 0.5]}],
          "shapes": [{"type": "quad", "material": "bumpy", "corner": [-1, 0, 1], "edge_u": [2, 0, 0], "edge_v": [0, 0, -2]}],
          "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": [1, 1, 1]}]
        })");
        s["materials"][0]["normal_map"] = normalMap;
        return s;
    }
};

}  // namespace

TEST_F(NormalMapLoadingTest, GltfNormalTextureIsLinearWithScaleTransformAndTangents) {
#ifndef PHOTONCL_HAVE_GLTF
    PCL_REQUIRE_FEATURE(false, "glTF support (tinygltf)");
#endif
    const Scene s = loadScene(write("quad.gltf", gltf().dump()));
    const Material& m = s.materials[size_t(s.meshes[0].material)];
    ASSERT_EQ(m.normalTexture, 0);
    EXPECT_EQ(m.rhoDTexture, -1);
    EXPECT_EQ(m.normalScale, 0.5f);
    const Texture& t = s.textures[0];
    // Linear: the file's code 128 reads as 128/255, not as its sRGB decoding (0.216).
    EXPECT_NEAR(t.image.at(0, 0).x, 128.0f / 255.0f, 1e-6f);
    EXPECT_NEAR(t.image.at(0, 0).z, 1.0f, 1e-6f);
    EXPECT_EQ(t.transform.scale[0], 2.0f);
    EXPECT_EQ(t.wrapU, TextureWrap::Mirror);
    ASSERT_EQ(s.meshes[0].tangents.size(), 16u);
    EXPECT_EQ(s.meshes[0].tangents[0], 1.0f);
    EXPECT_EQ(s.meshes[0].tangents[3], 1.0f);
}

TEST_F(NormalMapLoadingTest, GltfTangentsFollowTheNodeAndMirrorFlipsW) {
#ifndef PHOTONCL_HAVE_GLTF
    PCL_REQUIRE_FEATURE(false, "glTF support (tinygltf)");
#endif
    json d = gltf();
    d["nodes"][0]["rotation"] = {0.0, 0.0, std::sqrt(0.5), std::sqrt(0.5)};  // 90° about z: +x → +y
    Scene s = loadScene(write("turned.gltf", d.dump()));
    EXPECT_NEAR(s.meshes[0].tangents[0], 0.0f, 1e-6f);
    EXPECT_NEAR(s.meshes[0].tangents[1], 1.0f, 1e-6f);
    EXPECT_EQ(s.meshes[0].tangents[3], 1.0f);
    d = gltf();
    d["nodes"][0]["scale"] = {-1.0, 1.0, 1.0};  // a mirror: handedness flips
    s = loadScene(write("mirrored.gltf", d.dump()));
    EXPECT_NEAR(s.meshes[0].tangents[0], -1.0f, 1e-6f);
    EXPECT_EQ(s.meshes[0].tangents[3], -1.0f);
}

TEST_F(NormalMapLoadingTest, GltfWithoutTangentsGetsGeneratedOnes) {
#ifndef PHOTONCL_HAVE_GLTF
    PCL_REQUIRE_FEATURE(false, "glTF support (tinygltf)");
#endif
    json d = gltf();
    d["meshes"][0]["primitives"][0]["attributes"].erase("TANGENT");
    const Scene s = loadScene(write("quad.gltf", d.dump()));
    ASSERT_EQ(s.meshes[0].tangents.size(), 16u);
    // u runs along +x; v runs down the image, along −y here, so up the image is +y = N × T: w = 1.
    for (size_t v = 0; v < 4; ++v) {
        EXPECT_NEAR(s.meshes[0].tangents[4 * v], 1.0f, 1e-6f) << v;
        EXPECT_EQ(s.meshes[0].tangents[4 * v + 3], 1.0f) << v;
    }
}

TEST_F(NormalMapLoadingTest, BadGltfNormalMapsAreRefused) {
#ifndef PHOTONCL_HAVE_GLTF
    PCL_REQUIRE_FEATURE(false, "glTF support (tinygltf)");
#endif
    json d = gltf();
    d["materials"][0]["normalTexture"]["index"] = 4;
    expectError("a.gltf", d, {"normalTexture.index", "an integer in [-1, 0]", "4"});
    d = gltf();
    d["materials"][0]["normalTexture"]["scale"] = "big";
    expectError("b.gltf", d, {"normalTexture.scale", "a number", "big"});
    d = gltf();
    d["images"][0]["uri"] = "missing.png";
    expectError("c.gltf", d, {"images[0].uri", "missing.png", "no such file"});
    d = gltf();
    d["meshes"][0]["primitives"][0]["attributes"].erase("TEXCOORD_0");
    expectError("d.gltf", d, {"uv", "texture coordinates (set 0)", "got none"});
    d = gltf();
    d["accessors"][2]["type"] = "VEC3";
    expectError("e.gltf", d, {"accessors[2].type", "expected VEC4", "type code 3"});
}

TEST_F(NormalMapLoadingTest, JsonNormalMapWithTheTextureFields) {
    const Scene s = loadScene(write(
        "scene.json",
        jsonScene({{"texture", "normal.png"}, {"normal_scale", 2.0}, {"wrap", "clamp"}, {"scale", {3, 3}}}).dump()));
    const Material& m = s.materials[0];
    ASSERT_EQ(m.normalTexture, 0);
    EXPECT_EQ(m.normalScale, 2.0f);
    const Texture& t = s.textures[0];
    EXPECT_NEAR(t.image.at(0, 0).x, 128.0f / 255.0f, 1e-6f);  // linear by default
    EXPECT_EQ(t.wrapU, TextureWrap::Clamp);
    EXPECT_EQ(t.transform.scale[1], 3.0f);
    // The quad got 0..1 coordinates and generated tangents: u along edge_u (+x).
    ASSERT_EQ(s.meshes[0].tangents.size(), 16u);
    EXPECT_NEAR(s.meshes[0].tangents[0], 1.0f, 1e-6f);
    // "encoding": "srgb" decodes instead.
    const Scene srgb =
        loadScene(write("srgb.json", jsonScene({{"texture", "normal.png"}, {"encoding", "srgb"}}).dump()));
    EXPECT_NEAR(srgb.textures[0].image.at(0, 0).x, kGrey, 1e-6f);
}

TEST_F(NormalMapLoadingTest, BadJsonNormalMapsAreRefused) {
    expectError("a.json", jsonScene({{"texture", "nope.png"}}), {"materials[0].normal_map.texture", "nope.png"});
    expectError("b.json", jsonScene({{"texture", "normal.png"}, {"normal_scale", "x"}}),
                {"materials[0].normal_map.normal_scale", "a number"});
    expectError("c.json", jsonScene({{"texture", "normal.png"}, {"strength", 1}}),
                {"materials[0].normal_map.strength", "unknown key"});
    expectError("d.json", jsonScene("normal.png"), {"materials[0].normal_map", "an object"});
    json sphere = jsonScene({{"texture", "normal.png"}});
    sphere["shapes"][0] = json::parse(R"({"type": "sphere", "material": "bumpy", "centre": [0, 0, 0], "radius": 1})");
    expectError("e.json", sphere, {"spheres[0]", "an untextured material"});
}
