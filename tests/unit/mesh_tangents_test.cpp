// Tangent generation (scene/mesh_tangents.h, MikkTSpace-style) against surfaces whose tangents
// are known: a plane whose u runs along +x (T = +x; v running along −z makes up the image +z =
// −(N × T), so w = −1), the same plane with u mirrored (T = −x, w = +1), and a cylinder wrapped by u
// around its axis and v along it (T the circumference direction at every vertex, ⟂ its normal).
// Tolerances: 1e-5 on unit vectors (float rounding of the accumulation).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/test_scenes.h"
#include "scene/mesh_tangents.h"

using namespace pcl;
using namespace pcl::test_scenes;

namespace {

Vec3 tangentOf(const std::vector<float>& t, size_t v) { return {t[4 * v], t[4 * v + 1], t[4 * v + 2]}; }

}  // namespace

TEST(MeshTangents, PlaneGetsItsUDirectionAndHandedness) {
    Scene s;
    const int q = addQuad(s, Vec3(-1, 0, 1), Vec3(2, 0, 0), Vec3(0, 0, -2), 0);  // facing +y
    TriangleMesh& m = s.meshes[size_t(q)];
    m.uv[0] = {0, 0, 1, 0, 1, 1, 0, 1};
    std::vector<float> t = generateTangents(m, 0);
    for (size_t v = 0; v < 4; ++v) {
        const Vec3 T = tangentOf(t, v);
        EXPECT_NEAR(T.x, 1.0f, 1e-5f);
        EXPECT_NEAR(T.y, 0.0f, 1e-5f);
        EXPECT_NEAR(T.z, 0.0f, 1e-5f);
        // ∂p/∂v = −z (v runs down the image), so up the image is +z = N × T · w with N × T = −z.
        EXPECT_EQ(t[4 * v + 3], -1.0f) << v;
    }
    m.uv[0] = {1, 0, 0, 0, 0, 1, 1, 1};  // u mirrored: T = −x, handedness flips
    t = generateTangents(m, 0);
    for (size_t v = 0; v < 4; ++v) {
        EXPECT_NEAR(tangentOf(t, v).x, -1.0f, 1e-5f);
        EXPECT_EQ(t[4 * v + 3], 1.0f) << v;
    }
}

TEST(MeshTangents, CylinderGetsTheCircumferenceDirection) {
    // 24 segments around y, 3 rings; u = angle / 2π, v = 1 − y/2 (down the image is down the
    // axis); outward normals; the seam duplicated (u 0 and 1).
    TriangleMesh m;
    const int segments = 24, rings = 3;
    for (int r = 0; r < rings; ++r)
        for (int k = 0; k <= segments; ++k) {
            const float a = 6.2831853f * float(k) / float(segments), y = 2.0f * float(r) / float(rings - 1);
            m.positions.push_back(Vec3(std::cos(a), y, std::sin(a)));
            m.normals.push_back(Vec3(std::cos(a), 0, std::sin(a)));
            m.uv[0].push_back(float(k) / float(segments));
            m.uv[0].push_back(1.0f - y / 2.0f);
        }
    const uint32_t row = uint32_t(segments + 1);
    for (int r = 0; r + 1 < rings; ++r)
        for (int k = 0; k < segments; ++k) {
            const uint32_t a = uint32_t(r) * row + uint32_t(k), b = a + 1, c = a + row, d = c + 1;
            m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
        }
    const std::vector<float> t = generateTangents(m, 0);
    double worst = 0.0;
    for (size_t v = 0; v < m.positions.size(); ++v) {
        const Vec3 p = m.positions[v];
        const Vec3 want = normalize(Vec3(-p.z, 0.0f, p.x));  // ∂p/∂u ∝ d(cos a, ·, sin a)/da
        const Vec3 T = tangentOf(t, v);
        worst = std::max(worst, double(length(T - want)));
        EXPECT_NEAR(dot(T, m.normals[v]), 0.0f, 1e-5f) << v;
        // ∂p/∂v = −y·2: up the image is +y; N × T = (cos a, 0, sin a) × (−sin a, 0, cos a) = −y: w = −1.
        EXPECT_EQ(t[4 * v + 3], -1.0f) << v;
    }
    std::printf("[figure] cylinder tangents: worst |T − ∂p/∂u direction| %.2e over %zu vertices\n", worst,
                m.positions.size());
    EXPECT_LT(worst, 1e-5);
}
