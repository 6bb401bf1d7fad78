// Image textures in JSON scenes (scenes/README.md, "Textures"): a material's rho_d names an
// image, the loader decodes it (8-bit files as sRGB, float files as linear), keeps its wrap modes
// and transform, and gives quads their 0..1 coordinates and meshes their "uv"; bad textures are
// refused with the usual message (file, field, what was found, what was expected).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>
#include <unistd.h>

#include "common/optional_feature.h"
#include "common/scene_folder_test.h"
#include "common/textured_scenes.h"
#include "core/error.h"
#include "core/math.h"
#include "image/image_io.h"
#include "scene/load_scene.h"
#include "scene/texture_image.h"
#ifdef PHOTONCL_HAVE_OIIO
#include <OpenImageIO/imageio.h>
#endif

using namespace pcl;
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

class TextureLoaderTest : public test::SceneFolderTest {
protected:
    void SetUp() override {
        PCL_REQUIRE_FEATURE(haveOpenImageIO(), "OpenImageIO (EXR/PNG textures)");
        makeFolder("photoncl-texture-test");
        // A 4 × 2 linear EXR: texel (x, y) = (x/4, y/2, 0.5).
        Image img(4, 2);
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 4; ++x) img.set(x, y, Vec3(float(x) / 4.0f, float(y) / 2.0f, 0.5f));
        writeLinearImage(path("grad.exr"), img, ImageMetadata{});
    }
    // One quad with material "tex" whose rho_d is `rhoD`, under a directional light.
    static json scene(const json& rhoD) {
        json s = json::parse(R"({
          "camera": {"position": [0, 3, 0.01], "look_at": [0, 0, 0], "fov": 40, "resolution": [16, 16]},
          "materials": [{"name": "tex"}],
          "shapes": [{"type": "quad", "material": "tex", "corner": [-1, 0, 1], "edge_u": [2, 0, 0], "edge_v": [0, 0, -2]}],
          "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": [1, 1, 1]}]
        })");
        s["materials"][0]["rho_d"] = rhoD;
        return s;
    }
};

}  // namespace

TEST_F(TextureLoaderTest, LinearExrWithWrapTransformAndFactor) {
    const Scene s = load(scene({{"texture", "grad.exr"},
                                {"factor", {0.5, 1, 1}},
                                {"wrap", {"clamp", "mirror"}},
                                {"offset", {0.25, 0.5}},
                                {"scale", {2, 3}},
                                {"rotation", 90}}));
    ASSERT_EQ(s.textures.size(), 1u);
    const Texture& t = s.textures[0];
    EXPECT_EQ(s.materials[0].rhoDTexture, 0);
    EXPECT_EQ(s.materials[0].rhoD.x, 0.5f);
    EXPECT_EQ(s.materials[0].rhoD.y, 1.0f);
    ASSERT_EQ(t.image.width, 4);
    ASSERT_EQ(t.image.height, 2);
    EXPECT_EQ(t.image.at(3, 1).x, 0.75f);  // linear: stored values as they are
    EXPECT_EQ(t.image.at(3, 1).y, 0.5f);
    EXPECT_EQ(t.wrapU, TextureWrap::Clamp);
    EXPECT_EQ(t.wrapV, TextureWrap::Mirror);
    EXPECT_EQ(t.transform.offset[1], 0.5f);
    EXPECT_EQ(t.transform.scale[0], 2.0f);
    EXPECT_NEAR(t.transform.rotation, kPiD / 2, 1e-6);  // degrees in JSON, radians inside
    // The quad's default coordinates: (0,0), (1,0), (1,1), (0,1) at corner, +u, +u+v, +v.
    const std::vector<float> quadUv = {0, 0, 1, 0, 1, 1, 0, 1};
    EXPECT_EQ(s.meshes[0].uv[0], quadUv);
}

TEST_F(TextureLoaderTest, EightBitPngIsDecodedFromSrgb) {
    Image img(2, 1);
    img.set(0, 0, Vec3(0.0f, 1.0f, 0.5f));
    img.set(1, 0, Vec3(0.2f, 0.2f, 0.2f));
    ASSERT_TRUE(writeSrgbPng(path("c.png"), img));
    const Scene s = load(scene({{"texture", "c.png"}}));
    const Image& t = s.textures[0].image;
    EXPECT_EQ(t.at(0, 0).x, 0.0f);
    EXPECT_NEAR(t.at(0, 0).y, 1.0f, 1e-6f);
    // 8-bit quantisation of the sRGB code: within 0.5/255 of the code, ~0.002 in linear at 0.5.
    EXPECT_NEAR(t.at(0, 0).z, 0.5f, 0.003f);
    EXPECT_NEAR(t.at(1, 0).x, 0.2f, 0.002f);
    // "encoding": "linear" takes the codes as they are (0.5 linear is code ~0.735).
    const Scene raw = load(scene({{"texture", "c.png"}, {"encoding", "linear"}}));
    EXPECT_NEAR(raw.textures[0].image.at(0, 0).z, 0.735f, 0.003f);
}

TEST_F(TextureLoaderTest, MeshUvAndItsChecks) {
    json s = scene({{"texture", "grad.exr"}});
    s["shapes"][0] = json::parse(R"({"type": "mesh", "material": "tex", "positions": [0,0,0, 1,0,0, 0,0,-1],
                                      "indices": [0, 1, 2], "uv": [0, 0, 1, 0, 0.5, 1]})");
    const Scene ok = load(s);
    const std::vector<float> uv = {0, 0, 1, 0, 0.5f, 1};
    EXPECT_EQ(ok.meshes[0].uv[0], uv);
    s["shapes"][0]["uv"] = {0, 0, 1};
    expectError(s, {"shapes[0].uv", "expected 6 finite numbers (u, v per position)"});
    s["shapes"][0].erase("uv");
    expectError(s, {"uv", "texture coordinates (set 0)", "\"tex\"", "got none"});
}

TEST_F(TextureLoaderTest, BadTexturesAreRefused) {
    expectError(scene({{"texture", "nope.png"}}),
                {"materials[0].rho_d.texture", "expected an image file", "nope.png", "no such file"});
    write("junk.png", "not an image at all");
    expectError(scene({{"texture", "junk.png"}}),
                {"materials[0].rho_d.texture", "expected a readable image", "junk.png"});
    write("empty.pfm", "PF\n0 0\n-1.0\n");
    expectError(scene({{"texture", "empty.pfm"}}), {"materials[0].rho_d.texture", "at least 1x1", "empty.pfm"});
    Image bright(1, 1);
    bright.set(0, 0, Vec3(0.5f, 1.5f, 0.5f));
    writeLinearImage(path("bright.exr"), bright, ImageMetadata{});
    expectError(scene({{"texture", "bright.exr"}}), {"texels in [0, 1]", "1.5", "bright.exr", "texel (0, 0)"});
#ifdef PHOTONCL_HAVE_OIIO
    {  // two channels (grey + alpha): neither grey nor RGB(A)
        const std::string p = path("ga.png");
        auto out = OIIO::ImageOutput::create(p);
        ASSERT_TRUE(out);
        const OIIO::ImageSpec spec(2, 2, 2, OIIO::TypeDesc::UINT8);
        ASSERT_TRUE(out->open(p, spec));
        const unsigned char px[8] = {0, 255, 10, 255, 20, 255, 30, 255};
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px));
        out->close();
        expectError(scene({{"texture", "ga.png"}}), {"1 (grey), 3 (RGB) or 4 (RGBA) channels", "ga.png", "with 2"});
    }
#endif
    expectError(scene({{"texture", "grad.exr"}, {"wrap", "wobble"}}),
                {"materials[0].rho_d.wrap", "repeat, clamp or mirror", "wobble"});
    expectError(scene({{"texture", "grad.exr"}, {"scale", {1}}}), {"rho_d.scale", "2 finite numbers"});
    expectError(scene({{"texture", "grad.exr"}, {"tint", 1}}), {"rho_d.tint", "unknown key"});
    expectError(scene({{"texture", "grad.exr"}, {"factor", {2, 0, 0}}}), {"rho_d.factor", "3 numbers in [0,1]"});
    expectError(scene({{"texture", "../grad.exr"}}), {"rho_d.texture"});
    // A textured sphere has no coordinates.
    json sphere = scene({{"texture", "grad.exr"}});
    sphere["shapes"][0] = json::parse(R"({"type": "sphere", "material": "tex", "centre": [0, 0, 0], "radius": 1})");
    expectError(sphere, {"spheres[0]", "an untextured material", "with a texture"});
}
