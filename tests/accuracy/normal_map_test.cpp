// A normal-mapped plane under a directional light, per pixel against the closed form
// L = ρ/π · E · max(0, n'·l), n' the map's normal in world space: glTF's tangent space (rgb → 2 rgb
// − 1, x along the tangent ∂p/∂u, y up the image — toward decreasing v —, z along the vertex
// normal; x and y times the map's scale), with the plane's tangents generated from its texture
// coordinates (scene/mesh_tangents.h). The expected normals are written down from that
// convention here, independently of the code: the quad's u runs along +x and v along −z, so the
// tangent is +x and "up the image" is +z. Two maps:
//   - one constant tilted normal (every pixel: the same L);
//   - 4 × 4 cells of 2 × 2 texels, each cell's normal tilted ±0.4 along x and ±0.3 along y (a
//     pattern of slopes whose signs check the tangent and the bitangent's handedness), where only
//     pixels whose footprint lies in a cell's flat middle (between its texel centres: bilinear
//     filtering blends nothing in) are compared.
// A delta light and a plane that sees nothing else: no noise; every compared pixel must be
// within 1e-4 relative (float round-off) of L. Rendered by final gathering and progressive
// photon mapping on the device (direct light by shadow rays at the eye hit, the gather and photon
// parts zero) and by the reference path tracer. Direct visualisation is left out: it reads direct
// light from the global map, whose photons carry the geometric surface's cosine (kernels/README.md,
// "Shading normals": not corrected).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/prepared_render.h"
#include "common/textured_scenes.h"
#include "core/math.h"

using namespace pcl;
using namespace pcl::test_scenes;

namespace {

constexpr int kSize = 64;
const Vec3 kIrradiance(2.0f, 1.5f, 1.0f), kRho(0.8f, 0.7f, 0.6f);
const Vec3 kToLight = normalize(Vec3(0.5f, 1.0f, 0.3f));

// Tangent-space normal m encoded as a texel (rgb = (m + 1)/2, m normalised).
Vec3 encode(Vec3 m) { return (normalize(m) + Vec3(1.0f)) * 0.5f; }

// The world normal of tangent-space m (scale applied to x and y) on the quad: T = +x, B = +z, N = +y.
Vec3 worldNormal(Vec3 m, float scale) {
    const Vec3 t = normalize(m);  // the decoded texel 2 rgb − 1 (up to rounding)
    return normalize(Vec3(t.x * scale, t.z, t.y * scale));
}

Scene planeScene(Image map, float scale) {
    Scene s;
    s.path = "(normal-mapped plane)";
    const int t = addTexture(s, std::move(map));
    const int m = addMaterial(s, kRho);
    s.materials[size_t(m)].normalTexture = t;
    s.materials[size_t(m)].normalScale = scale;
    addQuadSeenFromAbove(s, m, kSize);
    addDirectionalLight(s, -kToLight, kIrradiance);
    return s;
}

Vec3 expected(Vec3 n) { return kRho / Vec3(kPi) * kIrradiance * std::max(0.0f, dot(n, kToLight)); }

// The cell pattern: texel (i, j) of an 8 × 8 map.
Vec3 cellNormal(int i, int j) { return Vec3((i / 2) % 2 ? -0.4f : 0.4f, (j / 2) % 2 ? -0.3f : 0.3f, 1.0f); }

struct Errors {
    int compared = 0;
    double worst = 0.0;  // max relative error over pixels and channels
};

// Pixels whose four footprint corners lie on the plane (and, for the cells, in one cell's flat
// middle) against L of that normal.
template <class NormalAt>
Errors compare(const Scene& scene, const Image& img, NormalAt normalAt) {
    Errors e;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            bool ok = true;
            Vec3 n(0.0f);
            for (float fx : {0.0f, 1.0f})
                for (float fy : {0.0f, 1.0f}) {
                    float u, v;
                    quadUvAt(scene.camera, x, y, fx, fy, u, v);
                    Vec3 c;
                    ok = ok && u > 0.0f && u < 1.0f && v > 0.0f && v < 1.0f && normalAt(u, v, c);
                    if (ok && (fx != 0.0f || fy != 0.0f) && !(c == n)) ok = false;
                    n = c;
                }
            if (!ok) continue;
            const Vec3 want = expected(n), got = img.at(x, y);
            for (int c = 0; c < 3; ++c) e.worst = std::max(e.worst, std::fabs(double(got[c]) - want[c]) / want[c]);
            ++e.compared;
        }
    return e;
}

template <typename NormalAt>
void renderAndCheck(const Scene& scene, const char* what, NormalAt normalAt, int minPixels) {
    auto p = test::prepare(scene);
    ASSERT_TRUE(p->buffers.normalMaps.mapped());
    PhotonRenderSettings s;
    s.passes = 2;
    s.strata = 2;
    s.gatherRays = 4;
    s.globalPhotons = 2000;
    s.causticPhotons = 2000;
    s.seed = 3;
    for (RenderMethod m : {RenderMethod::FinalGather, RenderMethod::Progressive, RenderMethod::PathTracing}) {
        const Image img = test::renderImage(*p, m, s, 4, 3, what);
        const Errors e = compare(p->scene, img, normalAt);
        std::printf("[figure] normal-mapped plane, %s, %s: %d pixels, worst |rel err| %.2e\n", what,
                    renderMethodName(m), e.compared, e.worst);
        EXPECT_GE(e.compared, minPixels) << what << " " << renderMethodName(m);
        EXPECT_LT(e.worst, 1e-4) << what << " " << renderMethodName(m);
    }
}

}  // namespace

TEST(NormalMap, ConstantTiltedNormalShadesEveryPixelAsTheClosedForm) {
    const Vec3 m(0.3f, 0.2f, 1.0f);
    const float scale = 1.5f;
    Image map(2, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) map.set(x, y, encode(m));
    const Vec3 n = worldNormal(m, scale);
    // The tilt must matter: a map ignored would give N·l instead.
    ASSERT_GT(std::fabs(dot(n, kToLight) - kToLight.y), 0.05f);
    renderAndCheck(
        planeScene(map, scale), "constant normal",
        [&](float, float, Vec3& c) {
            c = n;
            return true;
        },
        kSize * kSize / 2);
}

TEST(NormalMap, SlopePatternMatchesTheClosedFormInEveryCell) {
    Image map(8, 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) map.set(x, y, encode(cellNormal(x, y)));
    const float scale = 1.0f;
    auto normalAt = [&](float u, float v, Vec3& c) {
        // The flat middle of the cell: between the centres of its 2 × 2 texels.
        const float x = u * 8.0f - 0.5f, y = v * 8.0f - 0.5f;
        const int i = int(std::floor(x)), j = int(std::floor(y));
        if (i < 0 || j < 0 || i % 2 != 0 || j % 2 != 0) return false;
        c = worldNormal(cellNormal(i, j), scale);
        return true;
    };
    renderAndCheck(planeScene(map, scale), "4x4 slope cells", normalAt, 200);
}
