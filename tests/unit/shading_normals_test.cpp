// Shading normals on the host side: which triangles prep/shading_normals.cpp keeps (flat ones
// exported with normals keep zeros), the shared lookup kernels/shared/shading_frame.h (the
// interpolated normal, its orientation, the fall-backs), the adjoint factor, and the photon
// twin's scattering with a shading normal (the geometric side test and the factor). Exact or
// float-rounding tolerances (1e-6).
#include <gtest/gtest.h>

#include <cmath>

#include "common/smooth_scenes.h"
#include "prep/shading_normals.h"
#include "reference/trace_photons.h"
#include "shared/shading_frame.h"

using namespace pcl;
using namespace pcl::test_scenes;

namespace {

PclV3 v3(Vec3 v) { return sampling_v3(v.x, v.y, v.z); }

}  // namespace

TEST(ShadingNormals, FlatMeshesWithNormalsUploadNothing) {
    Scene s;
    const int m = addMaterial(s, Vec3(0.5f));
    const int q = addQuad(s, Vec3(-1, 0, 1), Vec3(2, 0, 0), Vec3(0, 0, -2), m);
    // Normals along the face (either orientation, unnormalised): flat.
    s.meshes[size_t(q)].normals = {Vec3(0, 2, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 3, 0)};
    const SceneGeometry g = SceneGeometry::build(s);
    EXPECT_TRUE(buildTriangleNormals(s, g).empty());
}

TEST(ShadingNormals, SmoothTrianglesKeepTheirVertexNormalsAndFlatOnesZeros) {
    Scene s;
    const int m = addMaterial(s, Vec3(0.5f));
    addQuad(s, Vec3(-1, 0, 1), Vec3(2, 0, 0), Vec3(0, 0, -2), m);  // no normals
    const int q = addQuad(s, Vec3(-1, 1, 1), Vec3(2, 0, 0), Vec3(0, 0, -2), m);
    s.meshes[size_t(q)].normals = {Vec3(0, 1, 0), Vec3(0.1f, 1, 0), Vec3(0, 1, 0), Vec3(0, 1, 0)};
    const SceneGeometry g = SceneGeometry::build(s);
    const std::vector<PclTriangleNormals> n = buildTriangleNormals(s, g);
    ASSERT_EQ(n.size(), g.triangleCount());
    int smooth = 0;
    for (uint32_t prim = 0; prim < g.triangleCount(); ++prim) {
        const PrimitiveRef ref = g.primitive(prim);
        bool zero = true;
        for (float f : n[prim].n) zero = zero && f == 0.0f;
        // Vertex 1 (tilted) is in the second quad's first triangle (0, 1, 2) only.
        const bool expectSmooth = ref.object == uint32_t(q) && ref.index == 0;
        EXPECT_EQ(zero, !expectSmooth) << prim;
        smooth += !zero;
        if (expectSmooth) {
            EXPECT_EQ(n[prim].n[3], 0.1f);
            EXPECT_EQ(n[prim].n[4], 1.0f);
        }
    }
    EXPECT_EQ(smooth, 1);
}

TEST(ShadingNormals, LookupInterpolatesNormalisesAndOrients) {
    PclTriangleNormals t{};
    const Vec3 n0(1, 1, 0), n1(0, 1, 0), n2(0, 1, 1);
    for (int k = 0; k < 3; ++k) {
        const Vec3 n = k == 0 ? n0 : (k == 1 ? n1 : n2);
        t.n[3 * k] = n.x;
        t.n[3 * k + 1] = n.y;
        t.n[3 * k + 2] = n.z;
    }
    const float bu = 0.25f, bv = 0.5f;
    const Vec3 want = normalize(n0 * 0.25f + n1 * bu + n2 * bv);
    for (float side : {1.0f, -1.0f}) {
        const PclV3 ng = sampling_v3(0.0f, side, 0.0f);
        const PclV3 ns = shading_normal(&t, nullptr, nullptr, nullptr, nullptr, 0, 0, 1, bu, bv, ng);
        EXPECT_NEAR(ns.x, side * want.x, 1e-6f);
        EXPECT_NEAR(ns.y, side * want.y, 1e-6f);
        EXPECT_NEAR(ns.z, side * want.z, 1e-6f);
        EXPECT_TRUE(shading_is_smooth(ns, ng));
    }
    // Spheres (prim ≥ triangleCount) and zero normals: the geometric normal, exactly.
    const PclV3 ng = sampling_v3(0.0f, 0.0f, 1.0f);
    const PclV3 a = shading_normal(&t, nullptr, nullptr, nullptr, nullptr, 0, 1, 1, bu, bv, ng);
    EXPECT_FALSE(shading_is_smooth(a, ng));
    const PclTriangleNormals zero{};
    EXPECT_FALSE(shading_is_smooth(shading_normal(&zero, nullptr, nullptr, nullptr, nullptr, 0, 0, 1, bu, bv, ng), ng));
}

TEST(ShadingNormals, NormalMapTexelTurnsIntoTheGltfTangentFrame) {
    // N = +y, t = +x (not unit, not ⟂: Gram–Schmidt), w = −1: B = (N × T)·w = +z.
    const PclV3 n = sampling_v3(0, 1, 0), t = sampling_v3(2.0f, 0.5f, 0.0f);
    const float flat[3] = {0.5f, 0.5f, 1.0f};
    const PclV3 a = shading_perturb(n, t, -1.0f, flat, 1.0f);
    EXPECT_NEAR(a.y, 1.0f, 1e-6f);
    // m = (0.4, −0.2, 0.8) scaled by 1.5 in x, y: n' ∝ 0.6 T − 0.3 B + 0.8 N = (0.6, 0.8, −0.3).
    const float rgb[3] = {0.7f, 0.4f, 0.9f};
    const PclV3 b = shading_perturb(n, t, -1.0f, rgb, 1.5f);
    const Vec3 want = normalize(Vec3(0.6f, 0.8f, -0.3f));
    EXPECT_NEAR(b.x, want.x, 1e-6f);
    EXPECT_NEAR(b.y, want.y, 1e-6f);
    EXPECT_NEAR(b.z, want.z, 1e-6f);
    // A tangent along the normal leaves no frame: N.
    const PclV3 c = shading_perturb(n, n, 1.0f, rgb, 1.0f);
    EXPECT_EQ(c.y, 1.0f);
}

TEST(ShadingNormals, AdjointFactorIsOneOnFlatSurfacesAndPbrtsRatioElsewhere) {
    const Vec3 ng(0, 0, 1), wIn = normalize(Vec3(1, 0, 1)), wOut = normalize(Vec3(-0.3f, 0.2f, 1));
    EXPECT_FLOAT_EQ(shading_adjoint(v3(ng), v3(ng), v3(wIn), v3(wOut)), 1.0f);
    const Vec3 ns = normalize(Vec3(0.2f, 0, 1));
    const float want = std::fabs(dot(wIn, ns)) * std::fabs(dot(wOut, ng)) /
                       (std::fabs(dot(wIn, ng)) * std::fabs(dot(wOut, ns)));
    EXPECT_NEAR(shading_adjoint(v3(ns), v3(ng), v3(wIn), v3(wOut)), want, 1e-6f);
    EXPECT_EQ(shading_adjoint(v3(ns), v3(ng), v3(Vec3(1, 0, 0)), v3(wOut)), 0.0f);  // grazing: 0, not ∞
}

TEST(ShadingNormals, PhotonTwinScattersInTheShadingFrameWithTheAdjointFactor) {
    PclMaterial m{};
    m.rhoD[0] = m.rhoD[1] = m.rhoD[2] = 0.5f;
    m.specular = PCL_SPECULAR_NONE;
    const Vec3 n(0, 0, 1), ns = normalize(Vec3(1, 0, 1)), d = normalize(Vec3(-1, 0, -1));
    int wrongSide = 0, diffuse = 0;
    for (int i = 0; i < 64; ++i) {
        const float u[4] = {0.1f, 0.5f, (i % 8 + 0.5f) / 8.0f, (i / 8 + 0.5f) / 8.0f};
        const ReferenceScatter s = scatterPhotonReference(m, d, n, ns, Vec3(1.0f), u);
        if (s.kind == ReferenceScatter::WrongSide) {
            ++wrongSide;
            EXPECT_EQ(s.power.x, 0.0f);
            continue;
        }
        ASSERT_EQ(s.kind, ReferenceScatter::Diffuse);
        ++diffuse;
        EXPECT_GT(dot(s.direction, n), 0.0f);
        // Φ ρd / P_d (P_d = 0.5: Φ stays 1) times the adjoint factor.
        const float adj = std::fabs(dot(-d, ns)) * std::fabs(dot(s.direction, n)) /
                          (std::fabs(dot(-d, n)) * std::fabs(dot(s.direction, ns)));
        EXPECT_NEAR(s.power.x, adj, 1e-5f * adj);
    }
    // The cosine lobe about a normal tilted 45° puts (π/4 − ½)/π ≈ 9 % of its directions below.
    EXPECT_GT(wrongSide, 0);
    EXPECT_GT(diffuse, 48);
    // The flat overload is the shading one with ns = n.
    const float u[4] = {0.1f, 0.5f, 0.3f, 0.7f};
    const ReferenceScatter a = scatterPhotonReference(m, d, n, Vec3(1.0f), u);
    const ReferenceScatter b = scatterPhotonReference(m, d, n, n, Vec3(1.0f), u);
    EXPECT_EQ(a.direction.x, b.direction.x);
    EXPECT_EQ(a.power.x, b.power.x);
}
