// glTF metallicRoughnessTexture (scenes/README.md, "Materials"): the texture is read as linear
// data (B metallic, G roughness, each times its factor), and at every texel ρd, ρs and the Phong
// exponent follow the documented formula from base colour = baseColorFactor × the sRGB base
// colour texel: ρs = base k + (1 − k) F0, ρd = base (1 − k)(1 − F0), n = 1/(2 r⁴) − 1/2 (at most
// 10⁴; a texel with n < 1 folds ρs into ρd). Checked through the kernels' lookup
// (texture_material_at on the packed buffers) and the reference's (surfaceAt) at every texel
// centre of a 2 × 2 texture, to 1e-6. The class: glossy with the texture even where the factors
// alone would make the material diffuse; a mirror stays a mirror (ρd, ρs per texel).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>
#include <unistd.h>

#include "common/optional_feature.h"
#include "common/scene_folder_test.h"
#include "image/image_io.h"
#include "prep/scene_buffers.h"
#include "prep/texture_buffers.h"
#include "reference/surface.h"
#include "scene/load_scene.h"
#include "scene/texture_image.h"
#include "shared/texture.h"

using namespace pcl;
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

const float kHalf = 128.0f / 255.0f;  // an 8-bit code of 128 read as linear data

class MetallicRoughnessTest : public test::SceneFolderTest {
protected:
    void SetUp() override {
#ifndef PHOTONCL_HAVE_GLTF
        PCL_REQUIRE_FEATURE(false, "glTF support (tinygltf)");
#endif
        PCL_REQUIRE_FEATURE(haveOpenImageIO(), "OpenImageIO (PNG textures)");
        makeFolder("photoncl-metallic-roughness");
        // The unit quad in z = 0, facing +z, TEXCOORD_0 upright (v down): position (x, y) has
        // uv (x, 1 − y); triangles (0, 1, 2) below the diagonal, (0, 2, 3) above.
        const float pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
        const float uv0[8] = {0, 1, 1, 1, 1, 0, 0, 0};
        const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
        std::string bin(sizeof pos + sizeof uv0 + sizeof idx, '\0');
        std::memcpy(&bin[0], pos, sizeof pos);
        std::memcpy(&bin[48], uv0, sizeof uv0);
        std::memcpy(&bin[80], idx, sizeof idx);
        std::ofstream(dir_ / "quad.bin", std::ios::binary) << bin;
        // Base colour (sRGB): white, red / code-128 grey, blue.
        Image base(2, 2);
        base.set(0, 0, Vec3(1.0f));
        base.set(1, 0, Vec3(1.0f, 0.0f, 0.0f));
        base.set(0, 1, Vec3(srgbToLinear(kHalf)));
        base.set(1, 1, Vec3(0.0f, 0.0f, 1.0f));
        ASSERT_TRUE(writeSrgbPng((dir_ / "base.png").string(), base));
        // Metallic-roughness: (G, B) = (1, 0), (code 128, 1) / (0, code 128), (1, 1). Written
        // through the sRGB encoder, so a linear value srgbToLinear(c) lands as code c exactly.
        Image mr(2, 2);
        mr.set(0, 0, Vec3(0.0f, 1.0f, 0.0f));
        mr.set(1, 0, Vec3(0.0f, srgbToLinear(kHalf), 1.0f));
        mr.set(0, 1, Vec3(0.0f, 0.0f, srgbToLinear(kHalf)));
        mr.set(1, 1, Vec3(0.0f, 1.0f, 1.0f));
        ASSERT_TRUE(writeSrgbPng((dir_ / "mr.png").string(), mr));
    }

    static json doc(double metallic, double roughness) {
        json d = json::parse(R"({
          "asset": {"version": "2.0"},
          "extensionsUsed": ["KHR_lights_punctual"],
          "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 683}]}},
          "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
          "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.5, 0.5, 3]},
                    {"translation": [0.5, 0.5, 2], "extensions": {"KHR_lights_punctual": {"light": 0}}}],
          "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.1}}],
          "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
          "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 1, 0.8, 1],
                                                  "baseColorTexture": {"index": 0},
                                                  "metallicRoughnessTexture": {"index": 1}}}],
          "textures": [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 0}],
          "samplers": [{"wrapS": 33071, "wrapT": 33071}],
          "images": [{"uri": "base.png"}, {"uri": "mr.png"}],
          "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}
          ],
          "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 12}
          ],
          "buffers": [{"uri": "quad.bin", "byteLength": 92}]
        })");
        d["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] = metallic;
        d["materials"][0]["pbrMetallicRoughness"]["roughnessFactor"] = roughness;
        return d;
    }
    Scene load(const json& d) {
        const std::string p = (dir_ / "quad.gltf").string();
        std::ofstream(p) << d.dump();
        return loadScene(p);
    }
};

// The documented mapping for one texel (in double, then compared with the float kernels).
struct Expected {
    Vec3 rhoD, rhoS;
    float exponent;
};
Expected mapping(Vec3 baseFactor, Vec3 baseTexel, double metallic, double roughness, bool glossy, float n0) {
    const double f0 = 0.04;
    Expected e;
    e.exponent = n0;
    for (int c = 0; c < 3; ++c) {
        const double base = double(baseFactor[c]) * baseTexel[c];
        e.rhoS[c] = float(base * metallic + (1 - metallic) * f0);
        e.rhoD[c] = float(base * (1 - metallic) * (1 - f0));
    }
    if (glossy) {
        const double a = roughness * roughness;
        const double n = a > 0 ? std::min(1e4, 0.5 / (a * a) - 0.5) : 1e4;
        if (n < 1) {
            e.rhoD = e.rhoD + e.rhoS;
            e.rhoS = Vec3(0.0f);
            e.exponent = 1.0f;
        } else {
            e.exponent = float(n);
        }
    }
    const float sum = maxComponent(e.rhoD + e.rhoS);
    if (sum > 1) {
        e.rhoD = e.rhoD / sum;
        e.rhoS = e.rhoS / sum;
    }
    return e;
}

// At the centre of texel (i, j) of the 2 × 2 textures: uv ((i + ½)/2, (j + ½)/2), position
// (u, 1 − v); (prim, b1, b2) of the quad's triangle there.
void texelHit(int i, int j, uint32_t& prim, float& b1, float& b2) {
    const float x = (float(i) + 0.5f) / 2.0f, y = 1.0f - (float(j) + 0.5f) / 2.0f;
    if (x >= y) {  // triangle 0: p = (b1 + b2, b2)
        prim = 0;
        b2 = y;
        b1 = x - y;
    } else {  // triangle 1: p = (b1, b1 + b2)
        prim = 1;
        b1 = x;
        b2 = y - x;
    }
}

void expectEveryTexel(const Scene& s, double metallicFactor, double roughnessFactor, bool glossy) {
    const SceneGeometry g = SceneGeometry::build(s);
    const SceneBuffers b = buildSceneBuffers(s, g);
    const uint32_t mat = uint32_t(s.meshes[0].material);
    const Vec3 baseTexels[2][2] = {{Vec3(1.0f), Vec3(srgbToLinear(kHalf))}, {Vec3(1, 0, 0), Vec3(0, 0, 1)}};
    const float green[2][2] = {{1.0f, 0.0f}, {kHalf, 1.0f}}, blue[2][2] = {{0.0f, kHalf}, {1.0f, 1.0f}};
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
            uint32_t prim;
            float b1, b2;
            texelHit(i, j, prim, b1, b2);
            const Expected e = mapping(Vec3(0.5f, 1.0f, 0.8f), baseTexels[i][j], metallicFactor * blue[i][j],
                                       roughnessFactor * green[i][j], glossy, b.materials[mat].exponent);
            // The kernels' and the twin's lookup.
            PclMaterial M = b.materials[mat];
            texture_material_at(b.textures.materialTextures.data(), b.textures.texels.data(),
                                b.textures.triangleUvs.data(), mat, prim, g.triangleCount(), b1, b2, &M);
            // The reference's (its own lookup into each texture's image, the shared mapping).
            PclHit hit{1.0f, b1, b2, prim};
            const PclRay ray = makeRay(Vec3(0.5f, 0.5f, 3.0f), Vec3(0, 0, -1), 0.0f);
            const SurfacePoint sp = surfaceAt(s, g, ray, hit);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(M.rhoD[c], e.rhoD[c], 1e-6f) << "texel " << i << "," << j << " channel " << c;
                EXPECT_NEAR(M.rhoS[c], e.rhoS[c], 1e-6f) << "texel " << i << "," << j << " channel " << c;
                EXPECT_NEAR(sp.rhoD[c], e.rhoD[c], 1e-6f) << "reference, texel " << i << "," << j;
                EXPECT_NEAR(sp.rhoS[c], e.rhoS[c], 1e-6f) << "reference, texel " << i << "," << j;
                EXPECT_LE(M.rhoD[c] + M.rhoS[c], 1.0f + 1e-6f);
            }
            EXPECT_NEAR(M.exponent, e.exponent, 1e-6f * std::max(1.0f, e.exponent)) << "texel " << i << "," << j;
            EXPECT_EQ(sp.exponent, M.exponent) << "texel " << i << "," << j;
        }
}

}  // namespace

TEST_F(MetallicRoughnessTest, GlossyTexelsFollowTheMapping) {
    // Roughness factor 1 alone would make the material diffuse; with the texture it is glossy.
    const Scene s = load(doc(1.0, 0.9));
    const Material& m = s.materials[size_t(s.meshes[0].material)];
    ASSERT_EQ(s.textures.size(), 2u);
    EXPECT_EQ(m.specular, SpecularKind::Glossy);
    EXPECT_TRUE(m.metallicRoughness.active);
    EXPECT_EQ(m.rhoDTexture, 0);
    EXPECT_EQ(m.exponentTexture, 1);
    // Linear data: the code-128 green texel reads 128/255, not its sRGB decoding (0.216).
    EXPECT_NEAR(s.textures[1].image.at(1, 0).y, kHalf, 1e-6f);
    EXPECT_NEAR(s.textures[0].image.at(0, 1).x, srgbToLinear(kHalf), 1e-6f);
    expectEveryTexel(s, 1.0, 0.9, true);
}

TEST_F(MetallicRoughnessTest, MirrorStaysAMirrorWithTexturedRhoDAndRhoS) {
    const Scene s = load(doc(0.7, 0.01));  // n(0.01) ≥ 10⁴: every texel is as smooth or smoother
    const Material& m = s.materials[size_t(s.meshes[0].material)];
    EXPECT_EQ(m.specular, SpecularKind::Mirror);
    expectEveryTexel(s, 0.7, 0.01, false);
}
