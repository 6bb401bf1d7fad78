// The photon methods in participating media (issue 17): progressive and direct visualisation on
// the shipped media scenes against their path-traced references, and the device render against
// the twin render of the same photons (the eye pass in media, the volume estimate, the sum).
// Single scattering comes from the eye pass's next-event estimation (equiangular), multiple
// scattering and the volume caustic from the volume maps by the beam radiance estimate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "accuracy/accuracy_common.h"
#include "common/prepared_render.h"
#include "common/test_scenes.h"
#include "render/device_stages.h"
#include "render/shared_photons.h"
#include "render/twin_stages.h"
#include "scene/validate.h"

using namespace pcl;
using namespace pcl::accuracy;
using test::expectFinite;
using test::prepareFile;

namespace {

PhotonRenderSettings mediaSettings(RenderMethod method) {
    PhotonRenderSettings s;
    s.method = method;
    s.passes = 8;
    s.strata = 2;
    s.lightSamples = 4;
    s.globalPhotons = 50000;
    s.causticPhotons = 50000;
    s.seed = 5;
    return s;
}

}  // namespace

// 64 wide, 8 passes × 4 spp, 50k + 50k photons a pass (a twentieth of a default render's work):
// progressive's mean within 2 % of the reference (the bound), relMSE under 0.05.
TEST(MediaRenderAccuracy, ProgressiveMatchesTheMediaReferences) {
    ASSERT_TRUE(haveOpenImageIO()) << "the references are EXR";
    for (const std::string& name : mediaScenes()) {
        const Image ref = readImage(referencePath(name));
        auto p = prepareFile(name, ref.width, ref.height);
        const PhotonRenderSettings s = mediaSettings(RenderMethod::Progressive);
        const PhotonRenderResult r = test::render(*p, s);
        const Image img = r.film.resolve();
        const ImageErrors e = compare(img, ref);
        std::printf(
            "[figure] %s progressive (64 wide, 8 passes x 4 spp, 50k+50k photons, %.1f s, volume stage %.1f s): "
            "%s\n",
            name.c_str(), r.times.total, r.times.volume, formatErrors(e).c_str());
        EXPECT_NEAR(e.meanRatio, 1.0, 0.02) << name;
        EXPECT_LT(e.relMse, 0.05) << name;
        expectFinite(r, img, name);
    }
}

// Against an independent reference: Mitsuba 3's volumetric path tracer on cornell-fog
// (tests/data/mitsuba-cornell-fog.exr, 4096 spp, mean 0.26632 ± 0.0002), the same settings as
// above: mean within 2 %.
TEST(MediaRenderAccuracy, ProgressiveMatchesMitsubaOnCornellFog) {
    ASSERT_TRUE(haveOpenImageIO()) << "the references are EXR";
    const Image ref = readImage(PHOTONCL_SOURCE_DIR "/tests/data/mitsuba-cornell-fog.exr");
    auto p = prepareFile("media/cornell-fog.json", ref.width, ref.height);
    const PhotonRenderResult r = test::render(*p, mediaSettings(RenderMethod::Progressive));
    const Image img = r.film.resolve();
    const ImageErrors e = compare(img, ref);
    std::printf("[figure] media/cornell-fog.json progressive vs Mitsuba 3: %s\n", formatErrors(e).c_str());
    EXPECT_NEAR(e.meanRatio, 1.0, 0.02);
    expectFinite(r, img, "cornell-fog vs Mitsuba");
}

// The whole render on the device and on the twin (the twin replaying the device's photons), 24
// pixels wide, progressive and direct: 99 % of the pixel channels within 1e-3 relative (the rest:
// float rounding of a segment's end or an equiangular sample moving a photon across the beam's edge).
TEST(MediaRenderAccuracy, DeviceAndTwinRenderTheSameMediaImage) {
    for (const std::string& name : mediaScenes()) {
        auto p = prepareFile(name, 24, 24);
        for (RenderMethod method : {RenderMethod::Progressive, RenderMethod::DirectVisualisation}) {
            PhotonRenderSettings s = mediaSettings(method);
            s.passes = 2;
            s.strata = 1;
            s.globalPhotons = 20000;
            s.causticPhotons = 20000;
            PhotonPassRecord photons;
            Image device, twin;
            {
                DeviceRenderStages stages(test::testDevice(), p->scene, *p->geometry, p->buffers, s);
                SharedPhotonStages recording(stages, photons, SharedPhotonStages::Mode::Record);
                device = renderPhotonMapped(recording, p->scene, *p->geometry, p->buffers, p->plan, s).film.resolve();
            }
            TwinRenderStages stages(p->scene, *p->geometry, p->buffers);
            SharedPhotonStages replaying(stages, photons, SharedPhotonStages::Mode::Replay);
            const Image tw =
                renderPhotonMapped(replaying, p->scene, *p->geometry, p->buffers, p->plan, s).film.resolve();
            size_t close = 0;
            double worst = 0.0, sumD = 0.0, sumT = 0.0;
            for (size_t i = 0; i < device.rgb.size(); ++i) {
                const double d = device.rgb[i], t = tw.rgb[i];
                const double rel = std::abs(d - t) / std::max(std::abs(t), 1e-3);
                worst = std::max(worst, rel);
                close += rel < 1e-3;
                sumD += d;
                sumT += t;
            }
            const double share = double(close) / double(device.rgb.size());
            std::printf("[figure] %s %s device vs twin (24 wide, 2 passes): %.2f %% of pixel channels within 1e-3, "
                        "worst %.2e, means %.6f / %.6f\n",
                        name.c_str(), renderMethodName(method), 100.0 * share, worst, sumD / device.rgb.size(),
                        sumT / tw.rgb.size());
            EXPECT_GE(share, 0.99) << name << " " << renderMethodName(method);
            EXPECT_NEAR(sumD / sumT, 1.0, 1e-3) << name << " " << renderMethodName(method);
        }
    }
}

// The white furnace in fog, rendered by the photon methods: a closed box of albedo ρ emitting Le
// inward everywhere, filled with a non-absorbing medium. A uniform, isotropic radiance field
// L = Le/(1−ρ) solves the transport equation there (MediumAccuracy has the path tracer's version),
// so every pixel expects it, split between the eye pass (emission, direct light, single
// scattering) and the photon maps (surface and volume estimates). Energy lost or counted twice
// anywhere between the volume photons, the surface photons and the estimates shows as a mean off
// Le/(1−ρ); the estimates' kernels lose a little where their disc or sphere leaves the box.
// Measured (16 × 16, 8 passes × 4 spp, 50k photons): means 0.981–1.005 of Le/(1−ρ) over the three
// channels and both methods; the volume estimate ×1.08 moves red's to 1.037–1.039 (bound 3 %).
TEST(MediaRenderAccuracy, NonAbsorbingFogInTheFurnaceStaysUniform) {
    using namespace test_scenes;
    const float rho = 0.5f;
    const Vec3 Le(1.0f, 0.5f, 2.0f);
    Scene scene;
    addBox(scene, Vec3(-1), Vec3(1), addEmitter(scene, Vec3(rho), Le), -1, /*inward=*/true);
    scene.globalMedium = addMedium(scene, Vec3(0.0f), Vec3(1.0f, 2.0f, 0.5f), 0.5f);
    setCamera(scene, Vec3(0.1f, 0.2f, 0.8f), Vec3(0.1f, 0.1f, -1.0f), Vec3(0, 1, 0), 60.0f, 16, 16);
    const Vec3 expected = Le / (1.0f - rho);
    validateScene(scene);  // the box becomes an area light
    auto p = test::prepare(std::move(scene));
    for (RenderMethod method : {RenderMethod::Progressive, RenderMethod::DirectVisualisation}) {
        PhotonRenderSettings s = mediaSettings(method);
        s.causticPhotons = 0;
        const PhotonRenderResult r = test::render(*p, s);
        const Image img = r.film.resolve();
        expectFinite(r, img, renderMethodName(method));
        for (int c = 0; c < 3; ++c) {
            double mean = 0.0, lo = 1e30, hi = 0.0;
            const size_t n = img.rgb.size() / 3;
            for (size_t i = 0; i < n; ++i) {
                const double v = img.rgb[3 * i + size_t(c)];
                mean += v / double(n);
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
            std::printf("[figure] furnace in fog, %s, channel %d: mean / expected %.4f (pixels %.3f .. %.3f of "
                        "expected)\n",
                        renderMethodName(method), c, mean / expected[c], lo / expected[c], hi / expected[c]);
            EXPECT_NEAR(mean / expected[c], 1.0, 0.03) << renderMethodName(method) << " channel " << c;
        }
    }
}
