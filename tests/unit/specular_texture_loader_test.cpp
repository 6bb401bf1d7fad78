// ρs and exponent textures in JSON scenes (scenes/README.md, "Textures"): a mirror's or glossy
// lobe's "rho_s" may be a texture object (ρs = factor × the texture), a glossy "exponent" a
// texture object with a "range" [lo, hi] (exponent = lo + (hi − lo) R, the image read as linear
// unless "encoding" says srgb); bad ones are refused with the usual message (file, field, what
// was found, what was expected).
#include <gtest/gtest.h>

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

class SpecularTextureLoaderTest : public test::SceneFolderTest {
protected:
    void SetUp() override {
        PCL_REQUIRE_FEATURE(haveOpenImageIO(), "OpenImageIO (PNG textures)");
        makeFolder("photoncl-specular-texture");
        // A 2 × 1 PNG: codes 255 and 128 (grey).
        Image img(2, 1);
        img.set(0, 0, Vec3(1.0f));
        img.set(1, 0, Vec3(srgbToLinear(128.0f / 255.0f)));
        ASSERT_TRUE(writeSrgbPng((dir_ / "shine.png").string(), img));
    }
    // One quad with material "m" (rho_d 0.2 and `specular`) under a directional light.
    static json scene(const json& specular) {
        json s = json::parse(R"({
          "camera": {"position": [0, 3, 0.01], "look_at": [0, 0, 0], "fov": 40, "resolution": [16, 16]},
          "materials": [{"name": "m", "rho_d": [0.2, 0.2, 0.2]}],
          "shapes": [{"type": "quad", "material": "m", "corner": [-1, 0, 1], "edge_u": [2, 0, 0], "edge_v": [0, 0, -2]}],
          "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": [1, 1, 1]}]
        })");
        s["materials"][0]["specular"] = specular;
        return s;
    }
};

}  // namespace

TEST_F(SpecularTextureLoaderTest, GlossyRhoSAndExponentTextures) {
    const Scene s = load(scene({{"kind", "glossy"},
                                {"rho_s", {{"texture", "shine.png"}, {"factor", {0.5, 0.6, 0.7}}, {"wrap", "clamp"}}},
                                {"exponent", {{"texture", "shine.png"}, {"range", {10, 90}}, {"scale", {2, 2}}}}}));
    const Material& m = s.materials[0];
    EXPECT_EQ(m.specular, SpecularKind::Glossy);
    ASSERT_EQ(s.textures.size(), 2u);
    EXPECT_EQ(m.rhoSTexture, 0);
    EXPECT_EQ(m.exponentTexture, 1);
    EXPECT_EQ(m.rhoDTexture, -1);
    EXPECT_FLOAT_EQ(m.rhoS.x, 0.5f);
    EXPECT_FLOAT_EQ(m.rhoS.z, 0.7f);
    EXPECT_EQ(m.exponentRange[0], 10.0f);
    EXPECT_EQ(m.exponentRange[1], 90.0f);
    EXPECT_EQ(s.textures[0].wrapU, TextureWrap::Clamp);
    EXPECT_EQ(s.textures[1].transform.scale[0], 2.0f);
    // rho_s: an 8-bit file is sRGB by default; exponent: linear data by default.
    EXPECT_NEAR(s.textures[0].image.at(1, 0).x, srgbToLinear(128.0f / 255.0f), 1e-6f);
    EXPECT_NEAR(s.textures[1].image.at(1, 0).x, 128.0f / 255.0f, 1e-6f);
    EXPECT_FALSE(m.metallicRoughness.active);
}

TEST_F(SpecularTextureLoaderTest, MirrorRhoSTexture) {
    json j = scene({{"kind", "mirror"}, {"rho_s", {{"texture", "shine.png"}}}});
    j["materials"][0].erase("rho_d");  // ρd 0: the factor (1 without one) may reach 1
    const Scene s = load(j);
    EXPECT_EQ(s.materials[0].specular, SpecularKind::Mirror);
    EXPECT_EQ(s.materials[0].rhoSTexture, 0);
    EXPECT_FLOAT_EQ(s.materials[0].rhoS.y, 1.0f);
}

TEST_F(SpecularTextureLoaderTest, BadTexturesAreRefused) {
    const json tex = {{"texture", "shine.png"}};
    // A missing range, a reversed or non-positive one.
    expectError(scene({{"kind", "glossy"}, {"rho_s", {0.5, 0.5, 0.5}}, {"exponent", tex}}),
                {"materials[0].specular.exponent", "range", "0 < lo <= hi"});
    json reversed = tex;
    reversed["range"] = {50, 10};
    expectError(scene({{"kind", "glossy"}, {"rho_s", {0.5, 0.5, 0.5}}, {"exponent", reversed}}),
                {"materials[0].specular.exponent.range", "0 < lo <= hi", "[50,10]"});
    json zero = tex;
    zero["range"] = {0, 10};
    expectError(scene({{"kind", "glossy"}, {"rho_s", {0.5, 0.5, 0.5}}, {"exponent", zero}}),
                {"materials[0].specular.exponent.range", "0 < lo <= hi"});
    // A missing file, an unknown key, a factor that breaks ρd + ρs ≤ 1.
    expectError(scene({{"kind", "mirror"}, {"rho_s", {{"texture", "nothere.png"}}}}),
                {"materials[0].specular.rho_s.texture", "nothere.png"});
    expectError(scene({{"kind", "mirror"}, {"rho_s", {{"texture", "shine.png"}, {"range", {1, 2}}}}}),
                {"materials[0].specular.rho_s.range", "unknown key"});
    expectError(scene({{"kind", "mirror"}, {"rho_s", {{"texture", "shine.png"}, {"factor", {0.9, 0.9, 0.9}}}}}),
                {"materials[0]", "rho_d + rho_s <= 1", "1.1"});
    // A dielectric's rho_s stays a constant.
    expectError(scene({{"kind", "dielectric"}, {"rho_s", tex}}), {"materials[0].specular.rho_s", "3 numbers"});
    // A textured exponent on a sphere (no texture coordinates).
    json sphere = scene(
        {{"kind", "glossy"}, {"rho_s", {0.5, 0.5, 0.5}}, {"exponent", {{"texture", "shine.png"}, {"range", {1, 9}}}}});
    sphere["shapes"] = json::array({{{"type", "sphere"}, {"material", "m"}, {"centre", {0, 0, 0}}, {"radius", 0.5}}});
    expectError(sphere, {"spheres[0]", "an untextured material"});
}
