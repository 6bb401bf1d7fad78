// Emission textures as the loaders read them (scenes/README.md): a JSON material's "emission"
// as a texture object (factor × texture), glTF's emissiveTexture × emissiveFactor × emissive
// strength (sRGB decoded, its sampler, texCoord and KHR_texture_transform kept); the emitter
// becomes an area light, the flat buffers carry the slot and a triangle point reads factor ×
// the bilinear texel, in the kernels' lookup and the reference's alike; bad references are
// refused with the usual message. And the estimate of a triangle's mean radiance that chooses
// lights (prep/emission_texture.h): exact for untextured emitters, 0 where every texel read is
// black, the clamped texture's mean texel (the exact integral) over a whole quad within 3 % (a triangle whose
// box reaches a bright texel it does not cover falls back to one sample's worth of it).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "common/optional_feature.h"
#include "common/scene_folder_test.h"
#include "common/textured_scenes.h"
#include "core/error.h"
#include "geometry/scene_geometry.h"
#include "image/image_io.h"
#include "prep/emission_texture.h"
#include "prep/scene_buffers.h"
#include "scene/load_scene.h"
#include "scene/texture_image.h"
#include "shared/texture.h"

using namespace pcl;
using json = nlohmann::json;

namespace {

// The emitted radiance at barycentrics (bu, bv) of triangle `prim` through the flat buffers
// (the kernels' and the twin's lookup), beside the reference's emissionAt.
Vec3 bufferEmissionAt(const Scene& s, uint32_t prim, float bu, float bv) {
    const SceneGeometry g = SceneGeometry::build(s);
    const SceneBuffers b = buildSceneBuffers(s, g);
    const uint32_t mat = b.primInfo[prim].material;
    float le[3];
    texture_emission_at(b.textures.materialTextures.data(), b.textures.texels.data(), b.textures.triangleUvs.data(),
                        mat, prim, g.triangleCount(), bu, bv, b.materials[mat].emission, le);
    return Vec3(le[0], le[1], le[2]);
}

void expectNear(Vec3 a, Vec3 b, float tol, const std::string& what) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], tol) << what << " channel " << c;
}

class EmissionTextureLoaderTest : public test::SceneFolderTest {
protected:
    void SetUp() override {
        PCL_REQUIRE_FEATURE(haveOpenImageIO(), "OpenImageIO (PNG textures)");
        makeFolder("photoncl-emission-texture");
        // A 2 × 2 sRGB PNG: top row white and black, bottom row code-128 grey and red.
        Image img(2, 2);
        img.set(0, 0, Vec3(1.0f));
        img.set(1, 0, Vec3(0.0f));
        img.set(0, 1, Vec3(srgbToLinear(128.0f / 255.0f)));
        img.set(1, 1, Vec3(1.0f, 0.0f, 0.0f));
        ASSERT_TRUE(writeSrgbPng(path("glow.png"), img));
    }

    // One quad emitting `emission` (its coordinates: (0,0) at the corner, u along edge_u).
    static json jsonScene(const json& emission) {
        json s = json::parse(R"({
          "camera": {"position": [0, -3, 0.01], "look_at": [0, 0, 0], "fov": 40, "resolution": [16, 16]},
          "materials": [{"name": "floor", "rho_d": [0.5, 0.5, 0.5]}, {"name": "lamp"}],
          "shapes": [{"type": "quad", "material": "floor", "corner": [-2, -1, 2], "edge_u": [4, 0, 0], "edge_v": [0, 0, -4]},
                     {"type": "quad", "material": "lamp", "corner": [-1, 0, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2]}]
        })");
        s["materials"][1]["emission"] = emission;
        return s;
    }

    // The glTF quad of GltfTextureTest (z = 0, facing +z; TEXCOORD_1 = TEXCOORD_0 mirrored in u),
    // its material emissive with emissiveTexture.
    json gltfDoc() {
        const float pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
        const float uv0[8] = {0, 1, 1, 1, 1, 0, 0, 0};
        const float uv1[8] = {1, 1, 0, 1, 0, 0, 1, 0};
        const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
        std::string bin(sizeof pos + sizeof uv0 + sizeof uv1 + sizeof idx, '\0');
        std::memcpy(&bin[0], pos, sizeof pos);
        std::memcpy(&bin[48], uv0, sizeof uv0);
        std::memcpy(&bin[80], uv1, sizeof uv1);
        std::memcpy(&bin[112], idx, sizeof idx);
        std::ofstream(path("quad.bin"), std::ios::binary) << bin;
        return json::parse(R"({
          "asset": {"version": "2.0"},
          "extensionsUsed": ["KHR_materials_emissive_strength", "KHR_texture_transform"],
          "scene": 0, "scenes": [{"nodes": [0, 1]}],
          "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.5, 0.5, 3]}],
          "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.1}}],
          "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1, "TEXCOORD_1": 2}, "indices": 3, "material": 0}]}],
          "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0, "roughnessFactor": 1},
                         "emissiveFactor": [1, 0.5, 0.25],
                         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}},
                         "emissiveTexture": {"index": 0, "texCoord": 1,
                                             "extensions": {"KHR_texture_transform": {"scale": [0.5, 1]}}},
                         "occlusionTexture": {"index": 0}}],
          "textures": [{"source": 0, "sampler": 0}],
          "samplers": [{"wrapS": 33071, "wrapT": 33648}],
          "images": [{"uri": "glow.png"}],
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
    Scene loadGltf(const json& d) { return loadScene(write("quad.gltf", d.dump())); }
};

}  // namespace

TEST_F(EmissionTextureLoaderTest, JsonEmissionTextureIsFactorTimesTexture) {
    const Scene s = load(jsonScene({{"texture", "glow.png"}, {"factor", {10, 20, 30}}, {"wrap", "clamp"}}));
    const Material& m = s.materials[1];
    ASSERT_GE(m.emissionTexture, 0);
    EXPECT_TRUE(m.emits());
    expectNear(m.emission, Vec3(10, 20, 30), 0.0f, "factor");
    const Texture& t = s.textures[size_t(m.emissionTexture)];
    EXPECT_EQ(t.wrapU, TextureWrap::Clamp);
    EXPECT_NEAR(t.image.at(0, 1).x, srgbToLinear(128.0f / 255.0f), 1e-6f);  // 8-bit: sRGB decoded
    // The lamp is an area light; its triangle 0 is corner, +u, +u+v (uv (0,0), (1,0), (1,1)).
    // Barycentrics (0.5, 0.25): uv (0.75, 0.25), the black top-right texel's centre: nothing.
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].type, LightType::Area);
    const uint32_t lampTri = 2;  // the floor's two triangles come first
    expectNear(bufferEmissionAt(s, lampTri, 0.5f, 0.25f), Vec3(0.0f), 0.0f, "black texel");
    // (0.25, 0.25): uv (0.5, 0.25) = halfway between white and black: factor / 2, both lookups.
    expectNear(bufferEmissionAt(s, lampTri, 0.25f, 0.25f), Vec3(5, 10, 15), 1e-5f, "buffers");
    expectNear(emissionAt(s, s.meshes[1], 0, 0.25f, 0.25f), Vec3(5, 10, 15), 1e-5f, "reference");
}

TEST_F(EmissionTextureLoaderTest, JsonDefaultFactorIsOneAndBadOnesAreRefused) {
    const Scene s = load(jsonScene({{"texture", "glow.png"}}));
    expectNear(s.materials[1].emission, Vec3(1.0f), 0.0f, "default factor");
    expectError(jsonScene({{"texture", "glow.png"}, {"factor", {1, -1, 1}}}),
                {"materials[1].emission.factor", "3 finite numbers >= 0"});
    expectError(jsonScene({{"texture", "missing.png"}}), {"emission.texture", "missing.png"});
    expectError(jsonScene({{"texture", "glow.png"}, {"range", {1, 2}}}), {"emission.range", "unknown key"});
    json sphere = jsonScene({{"texture", "glow.png"}});
    sphere["shapes"][1] = {{"type", "sphere"}, {"material", "lamp"}, {"centre", {0, 0, 0}}, {"radius", 0.5}};
    expectError(sphere, {"shapes[1]", "non-emissive material"});
}

TEST_F(EmissionTextureLoaderTest, GltfEmissiveTextureTimesFactorAndStrength) {
#ifndef PHOTONCL_HAVE_GLTF
    PCL_REQUIRE_FEATURE(false, "glTF support (tinygltf)");
#endif
    const Scene s = loadGltf(gltfDoc());
    const Material& m = s.materials[size_t(s.meshes[0].material)];
    ASSERT_GE(m.emissionTexture, 0);
    expectNear(m.emission, Vec3(4.0f, 2.0f, 1.0f), 1e-6f, "emissiveFactor × strength");
    const Texture& t = s.textures[size_t(m.emissionTexture)];
    EXPECT_EQ(t.texCoord, 1);
    EXPECT_EQ(t.wrapU, TextureWrap::Clamp);
    EXPECT_EQ(t.wrapV, TextureWrap::Mirror);
    EXPECT_EQ(t.transform.scale[0], 0.5f);
    EXPECT_NEAR(t.image.at(0, 1).x, 0.2158605f, 1e-6f);  // sRGB code 128 decoded
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].type, LightType::Area);
    // Triangle 0 (vertices 0, 1, 2), barycentrics (0.5, 0.5): vertices 1 and 2, TEXCOORD_1
    // (0, 1) and (0, 0) → (0, 0.5), scaled in u by 0.5 → (0, 0.5): the left column, halfway
    // between white and code-128 grey (clamped in u).
    const float grey = srgbToLinear(128.0f / 255.0f), mid = 0.5f * (1.0f + grey);
    const Vec3 want(4.0f * mid, 2.0f * mid, 1.0f * mid);
    expectNear(bufferEmissionAt(s, 0, 0.5f, 0.5f), want, 1e-5f, "buffers");
    expectNear(emissionAt(s, s.meshes[0], 0, 0.5f, 0.5f), want, 1e-5f, "reference");
}

TEST_F(EmissionTextureLoaderTest, GltfZeroFactorIgnoresTheTextureAndBadOnesAreRefused) {
#ifndef PHOTONCL_HAVE_GLTF
    PCL_REQUIRE_FEATURE(false, "glTF support (tinygltf)");
#endif
    json d = gltfDoc();
    d["materials"][0].erase("emissiveFactor");             // default [0, 0, 0]: emits nothing
    d["extensionsUsed"].push_back("KHR_lights_punctual");  // a point light instead
    d["extensions"]["KHR_lights_punctual"]["lights"] = json::array({{{"type", "point"}, {"intensity", 683}}});
    d["nodes"].push_back({{"translation", {0.5, 0.5, 2}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    d["scenes"][0]["nodes"].push_back(2);
    const Scene dark = loadGltf(d);
    EXPECT_LT(dark.materials[size_t(dark.meshes[0].material)].emissionTexture, 0);
    EXPECT_FALSE(dark.materials[size_t(dark.meshes[0].material)].emits());
    d = gltfDoc();
    d["images"][0]["uri"] = "missing.png";
    expectError("quad.gltf", d, {"images[0].uri", "missing.png", "no such file"});
    d = gltfDoc();
    d["materials"][0]["emissiveTexture"]["index"] = 3;
    expectError("quad.gltf", d, {"emissiveTexture.index", "an integer in [-1, 0]", "3"});
    d = gltfDoc();
    d["materials"][0]["emissiveTexture"]["texCoord"] = 2;
    expectError("quad.gltf", d, {"emissiveTexture.texCoord", "an integer in [0, 1]"});
    d = gltfDoc();
    d["meshes"][0]["primitives"][0]["attributes"].erase("TEXCOORD_1");
    expectError("quad.gltf", d, {"uv1", "texture coordinates (set 1)", "none"});
}

TEST(EmissionTextureEstimate, ExactUntexturedZeroOnBlackAndTheMeanOverAQuad) {
    using namespace test_scenes;
    Scene s;
    const int plain = addEmitter(s, Vec3(0.0f), Vec3(1.5f, 2.5f, 3.5f));
    addQuad(s, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1), plain);
    expectNear(meanEmission(s, s.meshes[0], 0), Vec3(1.5f, 2.5f, 3.5f), 0.0f, "untextured");

    // 16 × 16, black but for a bright 4 × 4 block at texels (10..13, 2..5): a triangle whose
    // footprint lies in texels 0..7 reads only black.
    Image img(16, 16);
    for (int y = 2; y < 6; ++y)
        for (int x = 10; x < 14; ++x) img.set(x, y, Vec3(1.0f, 0.5f, 0.25f));
    const int tex = addTexture(s, img, TextureWrap::Clamp, TextureWrap::Clamp);
    const int lamp = addTexturedEmitter(s, tex, Vec3(2.0f));
    const int black = addQuad(s, Vec3(0, 0, 0), Vec3(0.25f, 0, 0), Vec3(0, 0, 0.25f), lamp);
    s.meshes[size_t(black)].uv[0] = {0.0f, 0.0f, 0.25f, 0.0f, 0.25f, 0.25f, 0.0f, 0.25f};  // texels 0..3
    EXPECT_EQ(maxComponent(meanEmission(s, s.meshes[size_t(black)], 0)), 0.0f);
    EXPECT_EQ(maxComponent(meanEmission(s, s.meshes[size_t(black)], 1)), 0.0f);
    // The whole image on a unit quad (clamp): ∫ L = factor × mean texel = 2 × 16/256 × texel.
    // The block lies in triangle 0 (u > v); triangle 1's box reaches it, so its grid reads 0
    // and it falls back to one sample's worth of the largest texel (1/529 of it, g = 23): the
    // quad's mean comes out ~1.5 % high; within 3 %.
    const int whole = addTexturedQuad(s, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1), lamp);
    const Vec3 mean = (meanEmission(s, s.meshes[size_t(whole)], 0) + meanEmission(s, s.meshes[size_t(whole)], 1)) *
                      0.5f;
    const Vec3 want = Vec3(1.0f, 0.5f, 0.25f) * (2.0f * 16.0f / 256.0f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c] / want[c], 1.0, 0.03) << "channel " << c;
    const Vec3 fallback = meanEmission(s, s.meshes[size_t(whole)], 1);
    EXPECT_GT(fallback.x, 0.0f) << "the box reaches a bright texel: chosen, however rarely";
    EXPECT_LT(fallback.x, 2.0f * 0.01f);
}
