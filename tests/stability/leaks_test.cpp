// Corners and thin walls end to end: the estimate's failure modes at a wall
// thinner than the search radius and at a corner where three surfaces meet, through the whole
// renderer rather than the estimate stage alone (tests/stages/estimate_test.cpp d and c).
#include "stability/stability_common.h"

#include <algorithm>

#include "common/two_rooms.h"

using namespace pcl;
using namespace pcl::stability;

namespace {

double maxValue(const Image& img) {
    double m = 0.0;
    for (float v : img.rgb) m = std::max(m, double(v));
    return m;
}

}  // namespace

// Two rooms sharing a wall 0.01 thick (r_max 0.12: 12 × the wall), a point light in room A, the
// camera in room B looking at the shared wall, floor and ceiling (both coplanar with A's). With
// PhotonRenderSettings::visibility on, final gathering (asked for precomputed irradiance or the
// full estimate), direct visualisation and progressive read exactly zero in room B; with it off
// they leak (shown, so the test can fail). Room A, seen from inside, is lit (mean > 0.01).
// Found here and fixed (host/render/photon_renderer.cpp, fixed_radius_source): the option did
// not exist; then precomputed irradiance leaked with it on (its nearest-record lookup has no
// visibility test: fg with visibility now reads the full estimate), and progressive ignored it.
TEST(ThinWall, UnlitRoomReadsZeroWithVisibility) {
    Scene s;
    const int white = test::addMaterial(s, Vec3(0.7f));
    const float t = 0.01f;
    test::addRoom(s, Vec3(-1.0f, 0.0f, 0.0f), Vec3(-t / 2, 1.0f, 1.0f), white);
    test::addRoom(s, Vec3(t / 2, 0.0f, 0.0f), Vec3(1.0f, 1.0f, 1.0f), white);
    s.lights.push_back(test::pointLight(Vec3(-0.5f, 0.5f, 0.5f), Vec3(2.0f)));
    s.camera.position = Vec3(0.95f, 0.5f, 0.5f);
    s.camera.lookAt = Vec3(0.0f, 0.4f, 0.5f);
    s.camera.vfovDegrees = 100.0f;
    s.camera.width = s.camera.height = 24;
    auto roomB = prepare(s);
    s.camera.position = Vec3(-0.95f, 0.5f, 0.5f);
    s.camera.lookAt = Vec3(0.0f, 0.4f, 0.5f);
    auto roomA = prepare(s);

    struct Case {
        const char* name;
        RenderMethod method;
        GatherSource source;
    };
    for (const Case& c : {Case{"fg precomputed", RenderMethod::FinalGather, GatherSource::Precomputed},
                          Case{"fg estimate", RenderMethod::FinalGather, GatherSource::Estimate},
                          Case{"direct", RenderMethod::DirectVisualisation, GatherSource::Estimate},
                          Case{"progressive", RenderMethod::Progressive, GatherSource::Estimate}}) {
        for (bool visibility : {true, false}) {
            PhotonRenderSettings rs;
            rs.method = c.method;
            rs.gatherSource = c.source;
            rs.visibility = visibility;
            rs.globalPhotons = 20000;
            rs.causticPhotons = 0;
            rs.gatherRays = 16;
            rs.passes = c.method == RenderMethod::Progressive ? 2 : 1;
            rs.seed = 5;
            PhotonRenderResult b = render(*roomB, rs);
            Image ib = b.film.resolve();
            expectFinite(b, ib, c.name);
            const double leak = maxValue(ib), leakMean = accuracy::meanValue(ib);
            std::printf(
                "[figure] thin wall, %s, visibility %s: room B max %.4g mean %.4g (expected 0 with visibility)\n",
                c.name, visibility ? "on" : "off", leak, leakMean);
            if (visibility) {
                EXPECT_EQ(leak, 0.0) << c.name << ": light leaked into room B";
                PhotonRenderResult a = render(*roomA, rs);
                Image ia = a.film.resolve();
                expectFinite(a, ia, c.name);
                std::printf("[figure] thin wall, %s: room A mean %.4g\n", c.name, accuracy::meanValue(ia));
                EXPECT_GT(accuracy::meanValue(ia), 0.01) << c.name;
            } else {
                EXPECT_GT(leak, 0.0) << c.name << ": expected the coplanar floor to leak without visibility";
            }
        }
    }
}

// A corner where a floor meets two walls, lit by a directional light travelling towards the
// corner (so the walls, facing it, hold more photons per area than the floor). The floor
// reflects red only (ρ 0.5, 0, 0); the walls blue only: the floor's red radiance is exactly
// uniform (ρ/π E cosθ), while the walls' photons carry red flux that a failed normal test would
// add to it. Direct visualisation (k 200, box filter, r_max 0.3), a camera zoomed onto the
// 0.002 × 0.002 floor square at the corner (r ≈ 0.06 ≫ 0.002): the k nearest photons then lie
// in a quarter disc, so the estimate is a quarter of the interior's (the quarter-plane
// expectation, estimate_test c). Over 16 passes (each estimate's noise 7 %/4 = 1.8 %, the
// ratio's 2.5 %; the 0.002 square adds ~2 % of the disc beyond the quarter): corner / interior
// ≤ 0.25 × 1.12 and above 0.25 × 0.8; the edge (one wall) ≤ 0.5 × 1.12; the interior within 8 %
// of ρ/π E cos θ.
TEST(Corner, CornerReadsAtMostTheQuarterPlaneExpectation) {
    Scene s;
    const int floorM = test::addMaterial(s, Vec3(0.5f, 0.0f, 0.0f));
    const int wallM = test::addMaterial(s, Vec3(0.0f, 0.0f, 0.8f));
    TriangleMesh floor, walls;
    floor.material = floorM;
    walls.material = wallM;
    test::addQuad(floor, Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 0, 0));  // normal +y
    test::addQuad(walls, Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, 1, 1), Vec3(0, 0, 1));  // x = 0
    test::addQuad(walls, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0));  // z = 0
    s.meshes = {floor, walls};
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = normalize(Vec3(-1.0f, -1.0f, -1.0f));
    sun.irradiance = Vec3(1.0f);
    s.lights.push_back(sun);
    s.camera.width = s.camera.height = 8;
    s.camera.up = Vec3(0, 0, 1);
    auto at = [&](float x, float z, float w) {
        Scene c = s;
        c.camera.position = Vec3(x, 0.5f, z);
        c.camera.lookAt = Vec3(x, 0.0f, z);
        c.camera.vfovDegrees = float(2.0 * std::atan(w / 2 / 0.5) * 180.0 / M_PI);
        return prepare(c);
    };
    const float w = 0.002f;
    auto corner = at(w / 2, w / 2, w), edge = at(0.5f, w / 2, w), interior = at(0.5f, 0.5f, w);
    PhotonRenderSettings rs;
    rs.method = RenderMethod::DirectVisualisation;
    rs.globalPhotons = 50000;
    rs.causticPhotons = 0;
    rs.globalK = 200;
    rs.filter = EstimateFilter::Box;
    rs.maxRadius = 0.3f;
    rs.passes = 16;
    rs.seed = 7;
    auto red = [&](const Prepared& p, const char* what) {
        PhotonRenderResult r = render(p, rs);
        Image img = r.film.resolve();
        expectFinite(r, img, what);
        double sum = 0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) sum += img.at(x, y).x;
        return sum / (img.width * img.height);
    };
    const double in = red(*interior, "interior"), co = red(*corner, "corner"), ed = red(*edge, "edge");
    const double analytic = 0.5 / M_PI * (1.0 / std::sqrt(3.0));
    std::printf("[figure] corner: interior red %.5f (analytic rho/pi E cos %.5f, %+.1f%%), edge/interior %.4f "
                "(<= 0.5 x 1.12), corner/interior %.4f (<= 0.25 x 1.12, >= 0.25 x 0.8)\n",
                in, analytic, 100.0 * (in / analytic - 1.0), ed / in, co / in);
    EXPECT_NEAR(in / analytic, 1.0, 0.08);
    EXPECT_LE(co / in, 0.25 * 1.12);
    EXPECT_GE(co / in, 0.25 * 0.8);
    EXPECT_LE(ed / in, 0.5 * 1.12);
}
