// Tangent generation (scene/mesh_tangents.h, MikkTSpace) against surfaces whose tangents are
// known: a plane whose u runs along +x (T = +x; v running along −z makes up the image +z =
// −(N × T), so w = −1), the same plane with u mirrored (T = −x, w = +1), and a cylinder wrapped by u
// around its axis and v along it (T the circumference direction at every vertex, ⟂ its normal);
// and against MikkTSpace's reference implementation itself (tests/data/mikktspace-tangents.json,
// made by scripts/make_mikktspace_references.py from mikktspace.c): every corner's tangent within
// 2e-6 of it (float rounding: the two are compiled differently), its handedness and the vertex
// splits exactly. Tolerances on the analytic surfaces: 1e-5 on unit vectors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

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
    generateTangents(m, 0);
    std::vector<float> t = m.tangents;
    ASSERT_EQ(m.positions.size(), 4u);  // one tangent per vertex: nothing split
    for (size_t v = 0; v < 4; ++v) {
        const Vec3 T = tangentOf(t, v);
        EXPECT_NEAR(T.x, 1.0f, 1e-5f);
        EXPECT_NEAR(T.y, 0.0f, 1e-5f);
        EXPECT_NEAR(T.z, 0.0f, 1e-5f);
        // ∂p/∂v = −z (v runs down the image), so up the image is +z = N × T · w with N × T = −z.
        EXPECT_EQ(t[4 * v + 3], -1.0f) << v;
    }
    m.uv[0] = {1, 0, 0, 0, 0, 1, 1, 1};  // u mirrored: T = −x, handedness flips
    m.tangents.clear();
    generateTangents(m, 0);
    t = m.tangents;
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
    const size_t vertices = m.positions.size();
    generateTangents(m, 0);
    ASSERT_EQ(m.positions.size(), vertices);  // the seam is duplicated already: nothing split
    const std::vector<float>& t = m.tangents;
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

TEST(MeshTangents, MatchMikkTSpacesReferenceImplementation) {
    std::ifstream in(std::string(PHOTONCL_SOURCE_DIR) + "/tests/data/mikktspace-tangents.json");
    ASSERT_TRUE(in) << "tests/data/mikktspace-tangents.json";
    const nlohmann::json doc = nlohmann::json::parse(in);
    ASSERT_EQ(doc.at("cases").size(), 4u);
    for (const nlohmann::json& c : doc.at("cases")) {
        const std::string name = c.at("name");
        TriangleMesh m;
        const std::vector<float> p = c.at("positions"), n = c.at("normals"), uv = c.at("uv");
        const std::vector<float> want = c.at("corner_tangents");
        for (size_t v = 0; 3 * v < p.size(); ++v) m.positions.push_back(Vec3(p[3 * v], p[3 * v + 1], p[3 * v + 2]));
        for (size_t v = 0; 3 * v < n.size(); ++v) m.normals.push_back(Vec3(n[3 * v], n[3 * v + 1], n[3 * v + 2]));
        m.uv[0] = uv;
        m.indices = c.at("indices").get<std::vector<uint32_t>>();
        const TriangleMesh original = m;
        generateTangents(m, 0);
        ASSERT_EQ(m.indices.size(), original.indices.size()) << name;
        ASSERT_EQ(m.tangents.size(), 4 * m.positions.size()) << name;

        // Per corner: the same vertex data as before the split, MikkTSpace's tangent and sign.
        double worst = 0.0;
        std::set<std::pair<uint32_t, std::vector<float>>> distinct;  // (vertex, reference tangent)
        for (size_t k = 0; k < m.indices.size(); ++k) {
            const uint32_t v = m.indices[k], o = original.indices[k];
            EXPECT_EQ(m.positions[v], original.positions[o]) << name << " corner " << k;
            EXPECT_EQ(m.uv[0][2 * v], original.uv[0][2 * o]) << name << " corner " << k;
            if (!original.normals.empty()) {
                EXPECT_EQ(m.normals[v], original.normals[o]) << name;
            }
            const Vec3 T = tangentOf(m.tangents, v), W(want[4 * k], want[4 * k + 1], want[4 * k + 2]);
            worst = std::max(worst, double(length(T - W)));
            EXPECT_LT(length(T - W), 2e-6f) << name << " corner " << k;
            EXPECT_EQ(m.tangents[4 * v + 3], -want[4 * k + 3]) << name << " corner " << k << " (glTF w = −sign)";
            distinct.insert({o, std::vector<float>(want.begin() + std::ptrdiff_t(4 * k),
                                                   want.begin() + std::ptrdiff_t(4 * k + 4))});
        }
        // A vertex is split exactly where MikkTSpace gave its corners different tangents
        // (unused vertices stay as they are).
        std::set<uint32_t> used(original.indices.begin(), original.indices.end());
        EXPECT_EQ(m.positions.size(), original.positions.size() - used.size() + distinct.size()) << name;
        std::printf("[figure] MikkTSpace %-14s %3zu corners, worst |T − reference| %.2e, vertices %zu → %zu\n",
                    name.c_str(), m.indices.size(), worst, original.positions.size(), m.positions.size());
    }
}
