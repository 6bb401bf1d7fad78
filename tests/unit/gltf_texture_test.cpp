// glTF textures (scenes/README.md, "glTF: textures"): baseColorTexture from an image file beside
// the glTF is decoded from sRGB and multiplies the base-colour-derived ρd; TEXCOORD_0/1 are read
// per vertex, the textureInfo's texCoord and KHR_texture_transform (which may override it) and
// the sampler's wrap modes are kept; the texels reach the flat buffers and a triangle hit reads
// the expected value. Embedded images (a bufferView with its mimeType, as a .glb holds them, or a
// data: URI) decode to the same texels as the file, and a bad reference or image is refused with
// the usual message.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <nlohmann/json.hpp>
#include <unistd.h>

#include "common/optional_feature.h"
#include "common/scene_folder_test.h"
#include "core/error.h"
#include "image/image_io.h"
#include "prep/scene_buffers.h"
#include "prep/texture_buffers.h"
#include "scene/load_scene.h"
#include "scene/texture_image.h"
#include "shared/texture.h"

using namespace pcl;
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

class GltfTextureTest : public test::SceneFolderTest {
protected:
    void SetUp() override {
#ifndef PHOTONCL_HAVE_GLTF
        PCL_REQUIRE_FEATURE(false, "glTF support (tinygltf)");
#endif
        PCL_REQUIRE_FEATURE(haveOpenImageIO(), "OpenImageIO (PNG textures)");
        makeFolder("photoncl-gltf-texture");
        // The unit quad in z = 0, facing +z; TEXCOORD_0 puts the image upright (v down), TEXCOORD_1
        // is TEXCOORD_0 mirrored in u.
        const float pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
        const float uv0[8] = {0, 1, 1, 1, 1, 0, 0, 0};
        const float uv1[8] = {1, 1, 0, 1, 0, 0, 1, 0};
        const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
        std::string bin(sizeof pos + sizeof uv0 + sizeof uv1 + sizeof idx, '\0');
        std::memcpy(&bin[0], pos, sizeof pos);
        std::memcpy(&bin[48], uv0, sizeof uv0);
        std::memcpy(&bin[80], uv1, sizeof uv1);
        std::memcpy(&bin[112], idx, sizeof idx);
        std::ofstream(dir_ / "quad.bin", std::ios::binary) << bin;
        // A 2 × 2 sRGB PNG: top row white and black, bottom row code 0.5 grey and red.
        Image img(2, 2);
        img.set(0, 0, Vec3(1.0f));
        img.set(1, 0, Vec3(0.0f));
        img.set(0, 1, Vec3(srgbToLinear(128.0f / 255.0f)));
        img.set(1, 1, Vec3(1.0f, 0.0f, 0.0f));
        ASSERT_TRUE(writeSrgbPng((dir_ / "base.png").string(), img));
    }

    static json doc() {
        return json::parse(R"({
          "asset": {"version": "2.0"},
          "extensionsUsed": ["KHR_lights_punctual"],
          "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 683}]}},
          "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
          "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.5, 0.5, 3]},
                    {"translation": [0.5, 0.5, 2], "extensions": {"KHR_lights_punctual": {"light": 0}}}],
          "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.1}}],
          "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1, "TEXCOORD_1": 2}, "indices": 3, "material": 0}]}],
          "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 1, 1, 1], "metallicFactor": 0, "roughnessFactor": 1,
                                                  "baseColorTexture": {"index": 0}}}],
          "textures": [{"source": 0, "sampler": 0}],
          "samplers": [{"wrapS": 33071, "wrapT": 33648}],
          "images": [{"uri": "base.png"}],
          "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}
          ],
          "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 32},
            {"buffer": 0, "byteOffset": 112, "byteLength": 12}
          ],
          "buffers": [{"uri": "quad.bin", "byteLength": 124}]
        })");
    }
    std::string write(const json& d) {
        const std::string p = (dir_ / "quad.gltf").string();
        std::ofstream(p) << d.dump();
        return p;
    }
    // ρd at barycentrics (b1, b2) of triangle `prim` through the flat buffers (the kernels' lookup).
    static Vec3 rhoAt(const Scene& s, uint32_t prim, float b1, float b2) {
        const SceneGeometry g = SceneGeometry::build(s);
        const TextureBuffers b = buildTextureBuffers(s, g);
        const Material& m = s.materials[size_t(s.meshes[0].material)];
        PclMaterial M = buildSceneBuffers(s, g).materials[size_t(s.meshes[0].material)];
        EXPECT_EQ(M.rhoD[0], m.rhoD.x);
        texture_material_at(b.materialTextures.data(), b.texels.data(), b.triangleUvs.data(),
                            uint32_t(s.meshes[0].material), prim, g.triangleCount(), b1, b2, &M);
        return Vec3(M.rhoD[0], M.rhoD[1], M.rhoD[2]);
    }
};

}  // namespace

TEST_F(GltfTextureTest, BaseColorTextureLoadsWithItsSamplerAndCoordinates) {
    const Scene s = loadScene(write(doc()));
    ASSERT_EQ(s.textures.size(), 1u);
    const Texture& t = s.textures[0];
    const Material& m = s.materials[size_t(s.meshes[0].material)];
    EXPECT_EQ(m.rhoDTexture, 0);
    // ρd's constant from the factors: (1 − F0) b + F0 (F0 = 0.04; roughness 1 folds the coat
    // into the diffuse part), b = (0.5, 1, 1): the texture multiplies it.
    const float kd = 0.5f * 0.96f + 0.04f;
    EXPECT_NEAR(m.rhoD.x, kd, 1e-6f);
    EXPECT_NEAR(m.rhoD.y, 1.0f, 1e-6f);
    EXPECT_EQ(t.wrapU, TextureWrap::Clamp);
    EXPECT_EQ(t.wrapV, TextureWrap::Mirror);
    EXPECT_EQ(t.texCoord, 0);
    // sRGB decoded: code 0.5 grey is 0.214 linear; white 1, black 0.
    ASSERT_EQ(t.image.width, 2);
    EXPECT_NEAR(t.image.at(0, 0).x, 1.0f, 1e-6f);
    EXPECT_EQ(t.image.at(1, 0).x, 0.0f);
    EXPECT_NEAR(t.image.at(0, 1).x, srgbToLinear(128.0f / 255.0f), 1e-6f);
    EXPECT_NEAR(t.image.at(0, 1).x, 0.2158605f, 1e-6f);
    EXPECT_NEAR(t.image.at(1, 1).x, 1.0f, 1e-6f);
    EXPECT_EQ(t.image.at(1, 1).y, 0.0f);
    const std::vector<float> uv0 = {0, 1, 1, 1, 1, 0, 0, 0};
    EXPECT_EQ(s.meshes[0].uv[0], uv0);
    EXPECT_EQ(s.meshes[0].uv[1].size(), 8u);
    // Triangle 0 is vertices (0, 1, 2) with uv (0,1), (1,1), (1,0). Barycentrics (0.25, 0.5):
    // uv = 0.25 (0,1) + 0.25 (1,1) + 0.5 (1,0) = (0.75, 0.5): halfway down between the black
    // texel (top right) and the red one (bottom right).
    const Vec3 rho = rhoAt(s, 0, 0.25f, 0.5f);
    EXPECT_NEAR(rho.x, kd * 0.5f, 1e-6f);
    EXPECT_NEAR(rho.y, 0.0f, 1e-6f);
    // At the white texel's centre, uv (0.25, 0.25): triangle 1 = (0, 2, 3) with uv (0,1), (1,0),
    // (0,0): (0.25, 0.25) = 0.25 v0 + 0.25 v2 + 0.5 v3.
    const Vec3 white = rhoAt(s, 1, 0.25f, 0.5f);
    EXPECT_NEAR(white.x, kd, 1e-6f);
    EXPECT_NEAR(white.y, 1.0f, 1e-6f);
}

TEST_F(GltfTextureTest, TexCoordAndKhrTextureTransform) {
    json d = doc();
    d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json::parse(
        R"({"index": 0, "texCoord": 0, "extensions": {"KHR_texture_transform": {"offset": [0.5, 0.25], "rotation": 0.5, "scale": [2, 3], "texCoord": 1}}})");
    d["extensionsUsed"] = {"KHR_lights_punctual", "KHR_texture_transform"};
    d["extensionsRequired"] = {"KHR_texture_transform"};
    const Scene s = loadScene(write(d));
    const Texture& t = s.textures[0];
    EXPECT_EQ(t.texCoord, 1);  // the extension's texCoord overrides the textureInfo's
    EXPECT_EQ(t.transform.offset[0], 0.5f);
    EXPECT_EQ(t.transform.offset[1], 0.25f);
    EXPECT_EQ(t.transform.scale[1], 3.0f);
    EXPECT_EQ(t.transform.rotation, 0.5f);  // radians, as glTF gives it
}

// base64 (RFC 4648) for data: URIs.
static std::string base64(const std::string& bytes) {
    static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 2]));
        out += k[(v >> 18) & 63];
        out += k[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? k[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? k[v & 63] : '=';
    }
    return out;
}

TEST_F(GltfTextureTest, EmbeddedImagesDecodeAsTheFileDoes) {
    const Scene fromFile = loadScene(write(doc()));
    ASSERT_EQ(fromFile.textures.size(), 1u);
    std::ifstream in(dir_ / "base.png", std::ios::binary);
    const std::string png((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(png.size(), 8u);
    auto expectSameTexels = [&](const Scene& s, const char* how) {
        ASSERT_EQ(s.textures.size(), 1u) << how;
        EXPECT_EQ(s.textures[0].image.rgb, fromFile.textures[0].image.rgb) << how;
        EXPECT_EQ(s.materials[size_t(s.meshes[0].material)].rhoDTexture, 0) << how;
    };
    // In a buffer, as a .glb's BIN chunk holds it: a bufferView and its mimeType.
    std::ofstream(dir_ / "image.bin", std::ios::binary) << png;
    json d = doc();
    d["buffers"].push_back({{"uri", "image.bin"}, {"byteLength", png.size()}});
    d["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 0}, {"byteLength", png.size()}});
    d["images"][0] = {{"bufferView", 4}, {"mimeType", "image/png"}};
    expectSameTexels(loadScene(write(d)), "bufferView");
    // A data: URI.
    d = doc();
    d["images"][0] = {{"uri", "data:image/png;base64," + base64(png)}};
    expectSameTexels(loadScene(write(d)), "data URI");

    auto expectError = [&](const json& bad, std::initializer_list<std::string> fragments) {
        try {
            loadScene(write(bad));
            ADD_FAILURE() << "loaded fine";
        } catch (const InputError& e) {
            const std::string msg = e.what();
            for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "lacks " << f << ": " << msg;
        }
    };
    json bad = doc();
    bad["buffers"].push_back({{"uri", "image.bin"}, {"byteLength", png.size()}});
    bad["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 0}, {"byteLength", png.size()}});
    bad["images"][0] = {{"bufferView", 4}};
    expectError(bad, {"images[0].mimeType", "required with a bufferView", "none"});
    bad["images"][0] = {{"bufferView", 4}, {"mimeType", "image/gif"}};
    expectError(bad, {"images[0].bufferView", "image/png or image/jpeg", "image/gif"});
    std::ofstream(dir_ / "image.bin", std::ios::binary) << std::string(png.size(), 'x');
    bad["images"][0] = {{"bufferView", 4}, {"mimeType", "image/png"}};
    expectError(bad, {"images[0].bufferView", "a readable image", "embedded image/png"});
    bad = doc();
    bad["images"][0] = {{"uri", "data:image/png;base64,@@@"}};
    expectError(bad, {"images[0].uri"});
}

TEST_F(GltfTextureTest, BadReferencesAreRefused) {
    auto expectError = [&](const json& d, std::initializer_list<std::string> fragments) {
        const std::string p = write(d);
        try {
            loadScene(p);
            ADD_FAILURE() << "loaded fine";
        } catch (const InputError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(p), std::string::npos) << msg;
            for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "lacks " << f << ": " << msg;
        }
    };
    json d = doc();
    d["images"][0]["uri"] = "missing.png";
    expectError(d, {"images[0].uri", "missing.png", "no such file"});
    d = doc();
    d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 3;
    expectError(d, {"baseColorTexture.index", "an integer in [-1, 0]", "3"});
    d = doc();
    d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 2;
    expectError(d, {"baseColorTexture.texCoord", "an integer in [0, 1]"});
    d = doc();
    d["samplers"][0]["wrapS"] = 1234;
    expectError(d, {"samplers[0].wrapS", "33071 (CLAMP_TO_EDGE)", "1234"});
    d = doc();
    d["meshes"][0]["primitives"][0]["attributes"].erase("TEXCOORD_0");
    expectError(d, {"uv", "texture coordinates (set 0)", "got none"});
    d = doc();
    std::ofstream(dir_ / "junk.png") << "not a png";
    d["images"][0]["uri"] = "junk.png";
    expectError(d, {"images[0].uri", "a readable image", "junk.png"});
}
