// The shared texture lookup (kernels/shared/texture.h, compiled for the host as the twin uses
// it) against values worked out by hand: bilinear weights at and between texel centres, the
// three wrap modes inside and outside [0, 1], KHR_texture_transform's offset, scale and
// rotation, and the packing of prep/texture_buffers (offsets, per-triangle coordinates).
// Tolerance 1e-6 absolute (texels are of order 1; the lookup is a few float operations).
#include <gtest/gtest.h>

#include <cmath>

#include "common/textured_scenes.h"
#include "core/math.h"
#include "prep/texture_buffers.h"
#include "scene/texture_image.h"
#include "shared/texture.h"

using namespace pcl;
using namespace pcl::test_scenes;

namespace {

constexpr float kTol = 1e-6f;

// A 2 × 2 texture whose red channel is a = 0 (top left), b = 1 (top right), c = 0.2 (bottom
// left), d = 0.6 (bottom right).
Texture twoByTwo(TextureWrap wrap, TextureTransform t = {}) {
    Texture tex;
    tex.image = Image(2, 2);
    tex.image.set(0, 0, Vec3(0.0f, 0.5f, 0.5f));
    tex.image.set(1, 0, Vec3(1.0f, 0.5f, 0.5f));
    tex.image.set(0, 1, Vec3(0.2f, 0.5f, 0.5f));
    tex.image.set(1, 1, Vec3(0.6f, 0.5f, 0.5f));
    tex.wrapU = tex.wrapV = wrap;
    tex.transform = t;
    return tex;
}

float red(const Texture& tex, float u, float v) {
    float out[3];
    texture_bilinear(textureDescriptor(tex, 0), tex.image.rgb.data(), u, v, out);
    EXPECT_NEAR(out[1], 0.5f, kTol);  // a constant channel stays constant
    return out[0];
}

}  // namespace

TEST(TextureSampling, BilinearAtAndBetweenTexelCentres) {
    const Texture t = twoByTwo(TextureWrap::Clamp);
    EXPECT_NEAR(red(t, 0.25f, 0.25f), 0.0f, kTol);  // texel centres: the texel itself
    EXPECT_NEAR(red(t, 0.75f, 0.25f), 1.0f, kTol);
    EXPECT_NEAR(red(t, 0.25f, 0.75f), 0.2f, kTol);
    EXPECT_NEAR(red(t, 0.75f, 0.75f), 0.6f, kTol);
    EXPECT_NEAR(red(t, 0.5f, 0.25f), 0.5f, kTol);     // halfway along the top row: (a + b)/2
    EXPECT_NEAR(red(t, 0.5f, 0.5f), 0.45f, kTol);     // the middle: (a + b + c + d)/4
    EXPECT_NEAR(red(t, 0.375f, 0.25f), 0.25f, kTol);  // a quarter of the way from a to b
    // (u, v) = (0.625, 0.625): fx = fy = 0.75: 0.0625 a + 0.1875 b + 0.1875 c + 0.5625 d.
    EXPECT_NEAR(red(t, 0.625f, 0.625f), 0.1875f + 0.1875f * 0.2f + 0.5625f * 0.6f, kTol);
}

TEST(TextureSampling, WrapModesOnTheTopRow) {
    const Texture rep = twoByTwo(TextureWrap::Repeat), cla = twoByTwo(TextureWrap::Clamp),
                  mir = twoByTwo(TextureWrap::Mirror);
    // u = 0: halfway between the last and first texel (repeat), the edge texel (clamp, mirror).
    EXPECT_NEAR(red(rep, 0.0f, 0.25f), 0.5f, kTol);
    EXPECT_NEAR(red(cla, 0.0f, 0.25f), 0.0f, kTol);
    EXPECT_NEAR(red(mir, 0.0f, 0.25f), 0.0f, kTol);
    // u = 1.75: repeat → 0.75 (b); clamp → b; mirror → 0.25 reflected (a).
    EXPECT_NEAR(red(rep, 1.75f, 0.25f), 1.0f, kTol);
    EXPECT_NEAR(red(cla, 1.75f, 0.25f), 1.0f, kTol);
    EXPECT_NEAR(red(mir, 1.75f, 0.25f), 0.0f, kTol);
    // u = −0.25: repeat → 0.75 (b); clamp → a; mirror → 0.25 (a).
    EXPECT_NEAR(red(rep, -0.25f, 0.25f), 1.0f, kTol);
    EXPECT_NEAR(red(cla, -0.25f, 0.25f), 0.0f, kTol);
    EXPECT_NEAR(red(mir, -0.25f, 0.25f), 0.0f, kTol);
    // u = 1.25: mirror → 0.75 reflected (b); −1.25: mirror → 0.75 (b); repeat → 0.25, 0.75.
    EXPECT_NEAR(red(mir, 1.25f, 0.25f), 1.0f, kTol);
    EXPECT_NEAR(red(mir, -1.25f, 0.25f), 1.0f, kTol);
    EXPECT_NEAR(red(rep, 1.25f, 0.25f), 0.0f, kTol);
    EXPECT_NEAR(red(rep, -1.25f, 0.25f), 1.0f, kTol);
    // Far away: repeat by the fractional part, clamp to the edge, no integer overflow.
    EXPECT_NEAR(red(rep, 1000.25f, 0.25f), 0.0f, kTol);
    EXPECT_NEAR(red(cla, 1e30f, 0.25f), 1.0f, kTol);
    EXPECT_NEAR(red(cla, -1e30f, 0.25f), 0.0f, kTol);
    // v wraps the same way: v = 1.75 under repeat is the bottom row's centre.
    EXPECT_NEAR(red(rep, 0.25f, 1.75f), 0.2f, kTol);
}

TEST(TextureSampling, KhrTextureTransform) {
    // u' = 2u + 0.5 (scale 2, offset 0.5): u = 0.125 reads u' = 0.75 (b).
    TextureTransform t;
    t.scale[0] = 2.0f;
    t.offset[0] = 0.5f;
    EXPECT_NEAR(red(twoByTwo(TextureWrap::Repeat, t), 0.125f, 0.25f), 1.0f, kTol);
    // Rotation r = π/2 counter-clockwise: u' = cos r u − sin r v = −v, v' = sin r u + cos r v = u.
    // (u, v) = (0.25, −0.75) reads (0.75, 0.25) = b; unrotated it would read (0.25, 0.25) = a.
    TextureTransform r;
    r.rotation = float(kPiD / 2);
    EXPECT_NEAR(red(twoByTwo(TextureWrap::Repeat, r), 0.25f, -0.75f), 1.0f, 1e-5f);
    EXPECT_NEAR(red(twoByTwo(TextureWrap::Repeat), 0.25f, -0.75f), 0.0f, kTol);
    // The descriptor's matrix is T R S: scale (2, 3), rotation 0.3, offset (0.1, 0.2).
    TextureTransform all;
    all.scale[0] = 2.0f;
    all.scale[1] = 3.0f;
    all.rotation = 0.3f;
    all.offset[0] = 0.1f;
    all.offset[1] = 0.2f;
    Texture tex = twoByTwo(TextureWrap::Repeat, all);
    const PclTexture d = textureDescriptor(tex, 0);
    float u, v;
    texture_transform_uv(d, 0.4f, 0.7f, &u, &v);
    const double c = std::cos(0.3), s = std::sin(0.3);
    EXPECT_NEAR(u, c * 2 * 0.4 - s * 3 * 0.7 + 0.1, 1e-6);
    EXPECT_NEAR(v, s * 2 * 0.4 + c * 3 * 0.7 + 0.2, 1e-6);
}

TEST(TextureSampling, GradientIsExactBetweenTexelCentres) {
    Texture tex;
    tex.image = gradientImage(5, 4);
    tex.wrapU = tex.wrapV = TextureWrap::Clamp;
    for (float u : {0.1f, 0.33f, 0.5f, 0.77f, 0.9f})
        for (float v : {0.125f, 0.4f, 0.61f, 0.875f}) {
            float out[3];
            texture_bilinear(textureDescriptor(tex, 0), tex.image.rgb.data(), u, v, out);
            const Vec3 e = gradientAt(5, 4, u, v);
            EXPECT_NEAR(out[0], e.x, 1e-6f) << u << ", " << v;
            EXPECT_NEAR(out[1], e.y, 1e-6f) << u << ", " << v;
            EXPECT_NEAR(out[2], e.z, 1e-6f) << u << ", " << v;
        }
}

TEST(TextureSampling, SrgbDecoding) {
    EXPECT_EQ(srgbToLinear(0.0f), 0.0f);
    EXPECT_NEAR(srgbToLinear(1.0f), 1.0f, 1e-6f);
    EXPECT_NEAR(srgbToLinear(0.5f), 0.2140411f, 1e-6f);       // ((0.5 + 0.055)/1.055)^2.4
    EXPECT_NEAR(srgbToLinear(0.04f), 0.04f / 12.92f, 1e-9f);  // the linear toe
}

TEST(TextureBuffers, PackingAndTriangleCoordinates) {
    Scene s;
    const int plain = addMaterial(s, Vec3(0.5f));
    const int t0 = addTexture(s, gradientImage(3, 2));
    const int t1 =
        addTexture(s, checkerImage(4, 4, 1, Vec3(1.0f), Vec3(0.0f)), TextureWrap::Clamp, TextureWrap::Mirror);
    const int m0 = addMaterial(s, Vec3(1.0f)), m1 = addMaterial(s, Vec3(0.5f));
    s.materials[size_t(m0)].rhoDTexture = t0;
    s.materials[size_t(m1)].rhoDTexture = t1;
    addQuad(s, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), plain);       // no coordinates: triangles 0, 1
    addTexturedQuad(s, Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, 1, 0), m1);  // triangles 2, 3
    s.meshes[1].uv[1] = {9, 8, 7, 6, 5, 4, 3, 2};
    const SceneGeometry g = SceneGeometry::build(s);
    const TextureBuffers b = buildTextureBuffers(s, g);
    ASSERT_EQ(b.materialTextures.size(), 3u);
    for (int k = 0; k < PCL_TEXTURE_SLOTS; ++k) EXPECT_EQ(b.materialTextures[size_t(plain)].slot[k].width, 0u) << k;
    const PclTexture& d0 = b.materialTextures[size_t(m0)].slot[PCL_TEXTURE_RHO_D];
    const PclTexture& d1 = b.materialTextures[size_t(m1)].slot[PCL_TEXTURE_RHO_D];
    EXPECT_EQ(d0.offset, 0u);
    EXPECT_EQ(d0.width, 3u);
    EXPECT_EQ(d1.offset, 3u * 2u * 3u);  // after t0's 6 texels
    EXPECT_EQ(d1.wrap, PCL_WRAP_CLAMP | PCL_WRAP_MIRROR << 8);
    EXPECT_EQ(b.materialTextures[size_t(m1)].slot[PCL_TEXTURE_RHO_S].width, 0u);
    EXPECT_EQ(b.materialTextures[size_t(m1)].mapping, PCL_TEXTURE_MAP_PHONG);
    EXPECT_EQ(b.texels.size(), size_t(3 * 2 * 3 + 4 * 4 * 3));
    ASSERT_EQ(b.triangleUvs.size(), 4u);
    // Triangle 3 is (0, 2, 3): set 0 (0,0), (1,1), (0,1); set 1 (9,8), (5,4), (3,2).
    const float set0[6] = {0, 0, 1, 1, 0, 1}, set1[6] = {9, 8, 5, 4, 3, 2};
    for (int k = 0; k < 6; ++k) {
        EXPECT_EQ(b.triangleUvs[3].uv[0][k], set0[k]) << k;
        EXPECT_EQ(b.triangleUvs[3].uv[1][k], set1[k]) << k;
    }
    // A scene without textures packs no texels and no coordinates.
    Scene plainScene;
    addQuad(plainScene, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), addMaterial(plainScene, Vec3(0.5f)));
    const TextureBuffers none = buildTextureBuffers(plainScene, SceneGeometry::build(plainScene));
    EXPECT_FALSE(none.textured());
    EXPECT_TRUE(none.triangleUvs.empty());
    EXPECT_EQ(none.materialTextures.size(), 1u);
}

TEST(TextureBuffers, TexturedRhoDAtATriangleHit) {
    // texture_material_at (texture_rho_d): the material's constant times the texture at the
    // interpolated coordinates; ρs and the exponent untouched.
    Scene s;
    const int t = addTexture(s, gradientImage(5, 4), TextureWrap::Clamp, TextureWrap::Clamp);
    const int m = addMaterial(s, Vec3(0.5f, 1.0f, 0.8f));
    s.materials[size_t(m)].rhoDTexture = t;
    addTexturedQuad(s, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), m);
    const SceneGeometry g = SceneGeometry::build(s);
    const TextureBuffers b = buildTextureBuffers(s, g);
    // Triangle 0 is (0, 1, 2) with uv (0,0), (1,0), (1,1): barycentrics (0.3, 0.2) → uv (0.5, 0.2).
    PclMaterial M{};
    M.rhoD[0] = 0.5f, M.rhoD[1] = 1.0f, M.rhoD[2] = 0.8f;
    M.rhoS[0] = M.rhoS[1] = M.rhoS[2] = 0.1f;
    M.exponent = 7.0f;
    texture_material_at(b.materialTextures.data(), b.texels.data(), b.triangleUvs.data(), uint32_t(m), 0u,
                        g.triangleCount(), 0.3f, 0.2f, &M);
    const float* rho = M.rhoD;
    EXPECT_EQ(M.rhoS[0], 0.1f);
    EXPECT_EQ(M.exponent, 7.0f);
    const Vec3 e = gradientAt(5, 4, 0.5f, 0.2f) * Vec3(0.5f, 1.0f, 0.8f);
    EXPECT_NEAR(rho[0], e.x, 1e-6f);
    EXPECT_NEAR(rho[1], e.y, 1e-6f);
    EXPECT_NEAR(rho[2], e.z, 1e-6f);
}
