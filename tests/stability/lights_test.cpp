// Extreme lights: a tiny, very bright area light, and a light sealed in an
// opaque box.
//
// "The emission loop" in this code is runPhotonPass's batch loop (pipeline/photon_pass.cpp): it
// emits exactly PhotonPassOptions::globalPhotons + causticPhotons paths, in batches, each path
// ending within maxDepth bounces. It counts paths emitted, not photons stored, so its cap is the
// requested count and nothing a scene does can make it run longer: a sealed light stores zero
// photons after its N paths, and the renderer then shows what is true, a black image. These tests
// check that it ends, with finite numbers, and that the photon counts say what happened.
#include "stability/stability_common.h"

#include <algorithm>

using namespace pcl;
using namespace pcl::stability;

namespace {

// Cornell box with its lamp scaled by `shrink` about its centroid and the emission by 1/shrink²
// (the same power).
Scene cornellWithLampScaled(float shrink) {
    Scene s = accuracy::loadSceneAt("cornell-box.json", 32, 32);
    for (const Light& l : s.lights) {
        if (l.type != LightType::Area) continue;
        TriangleMesh& m = s.meshes[size_t(l.mesh)];
        Vec3 c(0.0f);
        for (Vec3 p : m.positions) c = c + p * (1.0f / m.positions.size());
        for (Vec3& p : m.positions) p = c + (p - c) * shrink;
        Material& mat = s.materials[size_t(m.material)];
        mat.emission = mat.emission * (1.0f / (shrink * shrink));
    }
    return s;
}

Image withoutEmitted(const PhotonRenderResult& r) {
    Image img = r.film.resolve(), e = r.aovs.emitted.resolve();
    for (size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] -= e.rgb[i];
    return img;
}

}  // namespace

// The Cornell lamp shrunk 1000× on each side (area 1e-6 of it, radiance 1e6 ×, the same power):
// final gathering, 32×32, 2 passes: every pixel finite, and the image without the lamp's own
// pixels (emitted AOV subtracted) within 3 % in the mean of the full-size lamp's (the softer
// shadows move light around, not in or out); relMSE between them below 0.05.
TEST(ExtremeLights, TinyVeryBrightLampRendersLikeTheFullLamp) {
    auto full = prepare(cornellWithLampScaled(1.0f)), tiny = prepare(cornellWithLampScaled(1e-3f));
    PhotonRenderSettings rs;
    rs.passes = 2;
    rs.strata = 2;
    rs.globalPhotons = 30000;
    rs.causticPhotons = 0;
    rs.gatherRays = 16;
    rs.aovs = true;
    rs.seed = 17;
    PhotonRenderResult a = render(*full, rs), b = render(*tiny, rs);
    expectFinite(a, a.film.resolve(), "full lamp");
    expectFinite(b, b.film.resolve(), "tiny lamp");
    const Image ia = withoutEmitted(a), ib = withoutEmitted(b);
    EXPECT_TRUE(allFinite(ib));
    ImageErrors e = compare(ib, ia);
    std::printf("[figure] tiny lamp (1e-3 x 1e-3 of the Cornell lamp, radiance x 1e6) vs full lamp, fg: %s "
                "(mean within 3%%, relMSE < 0.05)\n",
                formatErrors(e).c_str());
    EXPECT_NEAR(e.meanRatio, 1.0, 0.03);
    EXPECT_LT(e.relMse, 0.05);
}

// The Cornell lamp sealed under an opaque box (five faces, the ceiling the sixth): black inside
// (no diffuse part: every photon is absorbed, none stored) or white inside (photons stored, all
// inside the box). Every method ends after its passes, every pixel reads exactly 0, the photon
// counts say the paths were emitted (the cap) and, for the black box, that none was stored.
// Found here: with the white box, the photons on the ceiling inside the box leaked through the
// box's walls (0.05 thick, thinner than r_max) to the ceiling outside (max pixel 1.1-2.1 in
// fg/direct/progressive). The estimate's visibility test (PhotonRenderSettings::visibility, now
// honoured by every method) stops it; the test renders with it on.
TEST(ExtremeLights, LightSealedInAnOpaqueBoxEndsBlack) {
    for (float rho : {0.0f, 0.7f}) {
        Scene s = accuracy::loadSceneAt("cornell-box.json", 24, 24);
        Vec3 lo(1e30f), hi(-1e30f);
        for (const Light& l : s.lights)
            if (l.type == LightType::Area)
                for (Vec3 p : s.meshes[size_t(l.mesh)].positions) lo = vmin(lo, p), hi = vmax(hi, p);
        ASSERT_LT(lo.x, hi.x);
        const float ceiling = hi.y + 1e-4f, m = 0.02f;
        lo = lo - Vec3(m, 0, m);
        hi = hi + Vec3(m, 0, m);
        const float bottom = ceiling - 0.05f;
        const int boxM = test::addMaterial(s, Vec3(rho));
        TriangleMesh box;
        box.material = boxM;
        // Bottom (facing up, towards the lamp) and four sides, all facing in; the top edge
        // touches the ceiling.
        Vec3 c[8];
        for (int i = 0; i < 8; ++i)
            c[i] = Vec3(i & 1 ? hi.x : lo.x, i & 2 ? ceiling + 1e-3f : bottom, i & 4 ? hi.z : lo.z);
        test::addQuad(box, c[0], c[4], c[5], c[1]);  // bottom, +y
        test::addQuad(box, c[0], c[1], c[3], c[2]);  // z = lo, +z
        test::addQuad(box, c[4], c[6], c[7], c[5]);  // z = hi, −z
        test::addQuad(box, c[0], c[2], c[6], c[4]);  // x = lo, +x
        test::addQuad(box, c[1], c[5], c[7], c[3]);  // x = hi, −x
        s.meshes.push_back(box);
        validateScene(s);
        auto p = prepare(s);
        for (RenderMethod method :
             {RenderMethod::FinalGather, RenderMethod::DirectVisualisation, RenderMethod::Progressive}) {
            PhotonRenderSettings rs;
            rs.method = method;
            rs.passes = 2;
            rs.globalPhotons = 20000;
            rs.causticPhotons = 20000;
            rs.gatherRays = 8;
            rs.seed = 19;
            rs.visibility = true;
            PhotonRenderResult r = render(*p, rs);
            Image img = r.film.resolve();
            expectFinite(r, img, renderMethodName(method));
            double mx = 0.0;
            for (float v : img.rgb) mx = std::max(mx, double(std::abs(v)));
            std::printf("[figure] sealed lamp, box rho %.1f, %s: %llu paths emitted, %llu photons stored, max pixel %g "
                        "(expected 0)\n",
                        rho, renderMethodName(method), (unsigned long long)r.globalEmitted,
                        (unsigned long long)r.globalStored, mx);
            EXPECT_EQ(r.passes, 2u);
            EXPECT_EQ(r.globalEmitted, 2u * 20000u) << "the emission loop's cap is the requested count";
            if (rho == 0.0f) {
                EXPECT_EQ(r.globalStored, 0u);
            }
            EXPECT_EQ(mx, 0.0) << renderMethodName(method);
        }
    }
}
