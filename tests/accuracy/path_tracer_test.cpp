// Accuracy of the reference path tracer against closed-form answers. Each test builds its
// scene in code, renders a few hundred to a few thousand pixels, and states its tolerance
// beside the standard error it was chosen against.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "common/test_scenes.h"
#include "geometry/scene_geometry.h"
#include "image/film.h"
#include "reference/bsdf.h"
#include "reference/path_tracer.h"
#include "reference/sampling.h"

using namespace pcl;
using test_scenes::addEmitter;
using test_scenes::addMaterial;
using test_scenes::pinholeDirection;
using test_scenes::pixelAverageOnGround;
using test_scenes::setCamera;

namespace {

// A square (or rectangle) centred at c with front-side normal n, half-sizes hu, hv.
void addQuad(Scene& scene, int material, Vec3 c, Vec3 n, float hu, float hv, Vec3 motion = Vec3(0.0f),
             Vec3 uAxis = Vec3(0.0f)) {
    Vec3 u, unused;
    if (uAxis == Vec3(0.0f)) makeBasis(n, u, unused);
    else u = normalize(uAxis);
    Vec3 v = cross(n, u);  // cross(u, v) = n: counter-clockwise seen from the front
    TriangleMesh mesh;
    mesh.name = "quad" + std::to_string(scene.meshes.size());
    mesh.positions = {c - u * hu - v * hv, c + u * hu - v * hv, c + u * hu + v * hv, c - u * hu + v * hv};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.material = material;
    mesh.motion = motion;
    scene.meshes.push_back(mesh);
}

// The inside of the cube [-1,1]^3: every face's front side looks inward.
void addInwardBox(Scene& scene, int material) {
    const Vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (Vec3 n : axes) addQuad(scene, material, -n, n, 1.0f, 1.0f);
}

Image render(const Scene& scene, int spp, int maxDepth = 64, int threads = 2, uint64_t seed = 7) {
    // To tell noise from bias, rerun with more samples or another seed:
    // PHOTONCL_TEST_SPP_SCALE=16 PHOTONCL_TEST_SEED=3 accuracy_tests --gtest_filter='PathTracer*'
    if (const char* scale = std::getenv("PHOTONCL_TEST_SPP_SCALE")) spp *= std::max(1, std::atoi(scale));
    if (const char* s = std::getenv("PHOTONCL_TEST_SEED")) seed = std::strtoull(s, nullptr, 10);
    SceneGeometry geometry = SceneGeometry::build(scene);
    PathTracerSettings settings;
    settings.samplesPerPixel = spp;
    settings.maxDepth = maxDepth;
    settings.seed = seed;
    settings.threads = threads;
    return PathTracer(scene, geometry, settings).render().resolve();
}

double meanChannel(const Image& img, int c) {
    double s = 0.0;
    for (size_t i = 0; i < img.pixelCount(); ++i) s += img.rgb[3 * i + c];
    return s / static_cast<double>(img.pixelCount());
}

}  // namespace

// White furnace: a closed diffuse enclosure, albedo ρ, emitting Le inward everywhere. Radiance
// is the same everywhere and satisfies L = Le + ρ L, so L = Le / (1 - ρ).
TEST(PathTracerAccuracy, WhiteFurnace) {
    for (float rho : {0.5f, 0.8f}) {
        Scene scene;
        int m = addEmitter(scene, Vec3(rho), Vec3(1.0f, 0.5f, 2.0f));
        addInwardBox(scene, m);
        setCamera(scene, {0.2f, -0.1f, 0.3f}, {0.5f, 0.3f, -1.0f}, {0, 1, 0}, 90.0f, 16, 16);
        Image img = render(scene, rho < 0.7f ? 1024 : 2048, 256);  // ~2 s in all
        const Vec3 Le(1.0f, 0.5f, 2.0f);
        double worstPixel = 0.0;
        for (int c = 0; c < 3; ++c) {
            double expected = Le[c] / (1.0 - rho);
            double mean = meanChannel(img, c);
            std::printf("furnace rho %.1f channel %d: mean %.5f expected %.5f relative error %+.4f%%\n", rho, c, mean,
                        expected, 100.0 * (mean / expected - 1.0));
            EXPECT_NEAR(mean / expected, 1.0, 0.01) << "rho " << rho << " channel " << c;
            for (size_t i = 0; i < img.pixelCount(); ++i)
                worstPixel = std::max(worstPixel, std::abs(img.rgb[3 * i + c] / expected - 1.0));
        }
        std::printf("furnace rho %.1f: worst pixel relative error %.3f%%\n", rho, 100.0 * worstPixel);
        // A pixel averages 1024-2048 paths, σ ≈ 1.2 % (ρ 0.5) and 1.6 % (ρ 0.8): ~5σ over 768 values.
        EXPECT_LT(worstPixel, rho < 0.7f ? 0.06 : 0.09);
    }
}

// A point light of intensity I at height h over a diffuse plane, albedo ρ: the plane reflects
// L = ρ/π · I cosθ / r² (nothing else in the scene: no indirect light). Per pixel, against the
// analytic value averaged over the pixel's footprint.
TEST(PathTracerAccuracy, PointLightOverDiffusePlane) {
    Scene scene;
    int m = addMaterial(scene, Vec3(0.5f, 0.25f, 0.8f));
    addQuad(scene, m, Vec3(0.0f), Vec3(0, 1, 0), 50.0f, 50.0f);
    Light light;
    light.type = LightType::Point;
    light.position = {0.3f, 1.0f, -0.2f};
    light.intensity = Vec3(10.0f);
    scene.lights.push_back(light);
    setCamera(scene, {0.0f, 3.0f, 0.5f}, {0.0f, 0.0f, 0.0f}, {0, 0, -1}, 60.0f, 24, 24);
    Image img = render(scene, 256);

    double worst = 0.0, sumErr = 0.0;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x) {
            for (int c = 0; c < 3; ++c) {
                float rho = scene.materials[m].rhoD[c];
                double expected = pixelAverageOnGround(scene.camera, x, y, [&](Vec3 p) {
                    Vec3 d = light.position - p;
                    double r2 = dot(d, d), cosTheta = d.y / std::sqrt(r2);
                    return rho / kPi * light.intensity[c] * cosTheta / r2;
                });
                double err = std::abs(img.at(x, y)[c] / expected - 1.0);
                worst = std::max(worst, err);
                sumErr += err;
            }
        }
    std::printf("point light: worst pixel relative error %.4f%%, mean %.4f%%\n", 100.0 * worst,
                100.0 * sumErr / (24 * 24 * 3));
    EXPECT_LT(worst, 0.02);
}

// Spot and directional lights over the same plane: E = I(θ) cosθ / r² inside the inner cone,
// 0 outside the outer cone; a directional light gives L = ρ/π · E cosθ everywhere.
TEST(PathTracerAccuracy, SpotAndDirectionalLights) {
    Scene scene;
    int m = addMaterial(scene, Vec3(0.6f));
    addQuad(scene, m, Vec3(0.0f), Vec3(0, 1, 0), 50.0f, 50.0f);
    Light spot;
    spot.type = LightType::Spot;
    spot.position = {0.0f, 2.0f, 0.0f};
    spot.direction = {0, -1, 0};
    spot.intensity = Vec3(8.0f);
    spot.cosInner = std::cos(20.0f * kPi / 180.0f);  // radius 0.73 on the ground
    spot.cosOuter = std::cos(30.0f * kPi / 180.0f);  // radius 1.15
    scene.lights.push_back(spot);
    setCamera(scene, {0.0f, 4.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0, 0, -1}, 40.0f, 24, 24);  // ground ±1.46
    Image img = render(scene, 8);
    int inside = 0, outside = 0;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x) {
            Vec3 d = pinholeDirection(scene.camera, x, y, 0.5f, 0.5f);
            Vec3 p = scene.camera.position + d * (-scene.camera.position.y / d.y);
            float rad = std::sqrt(p.x * p.x + p.z * p.z);
            float halfPixel = 2.92f / 24.0f;  // pixels straddling a cone edge are not checked
            if (rad + halfPixel < 2.0f * std::tan(20.0f * kPi / 180.0f)) {
                double expected = pixelAverageOnGround(scene.camera, x, y, [&](Vec3 q) {
                    Vec3 l = spot.position - q;
                    double r2 = dot(l, l);
                    return 0.6 / kPi * 8.0 * (l.y / std::sqrt(r2)) / r2;
                });
                EXPECT_NEAR(img.at(x, y).x / expected, 1.0, 0.02) << x << "," << y;
                ++inside;
            } else if (rad - halfPixel > 2.0f * std::tan(30.0f * kPi / 180.0f)) {
                EXPECT_EQ(img.at(x, y).x, 0.0f) << x << "," << y;
                ++outside;
            }
        }
    EXPECT_GT(inside, 50);
    EXPECT_GT(outside, 50);

    scene.lights.clear();
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = normalize(Vec3(1.0f, -2.0f, 0.5f));
    sun.irradiance = Vec3(3.0f, 2.0f, 1.0f);
    scene.lights.push_back(sun);
    Image lit = render(scene, 1);
    float cosTheta = -sun.direction.y;
    for (int c = 0; c < 3; ++c) {
        double expected = 0.6 / kPi * sun.irradiance[c] * cosTheta;
        for (size_t i = 0; i < lit.pixelCount(); ++i)
            ASSERT_NEAR(lit.rgb[3 * i + c] / expected, 1.0, 1e-4) << i;  // deterministic: only float rounding
    }
}

// A square area light (radiance Le, facing down) over a diffuse plane. Irradiance from a
// uniform Lambertian polygon, Lambert's formula: E = Le/2 Σ_i Θ_i (n · γ_i), Θ_i the angle
// subtended by edge i and γ_i the unit normal of the plane through p and that edge (Arvo 1994).
TEST(PathTracerAccuracy, AreaLightOverDiffusePlane) {
    Scene scene;
    int ground = addMaterial(scene, Vec3(0.7f));
    int lamp = addEmitter(scene, Vec3(0.0f), Vec3(5.0f));
    addQuad(scene, ground, Vec3(0.0f), Vec3(0, 1, 0), 50.0f, 50.0f);
    addQuad(scene, lamp, Vec3(0.0f, 1.0f, 0.0f), Vec3(0, -1, 0), 0.25f, 0.25f, Vec3(0.0f), Vec3(1, 0, 0));
    Light area;
    area.type = LightType::Area;
    area.mesh = 1;
    scene.lights.push_back(area);
    setCamera(scene, {0.0f, 0.9f, 2.0f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 30.0f, 16, 16);
    Image img = render(scene, 2048);

    const Vec3 quad[4] = {{-0.25f, 1, -0.25f}, {0.25f, 1, -0.25f}, {0.25f, 1, 0.25f}, {-0.25f, 1, 0.25f}};
    auto irradiance = [&](Vec3 p) {
        double e = 0.0;
        for (int i = 0; i < 4; ++i) {
            Vec3 a = normalize(quad[i] - p), b = normalize(quad[(i + 1) % 4] - p);
            double theta = std::acos(std::min(1.0f, std::max(-1.0f, dot(a, b))));
            e += theta * dot(Vec3(0, 1, 0), normalize(cross(a, b)));
        }
        return 0.5 * 5.0 * std::abs(e);
    };
    double worst = 0.0, sumRatio = 0.0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            double expected =
                pixelAverageOnGround(scene.camera, x, y, [&](Vec3 p) { return 0.7 / kPi * irradiance(p); });
            double ratio = img.at(x, y).x / expected;
            worst = std::max(worst, std::abs(ratio - 1.0));
            sumRatio += ratio;
        }
    std::printf("area light: worst pixel relative error %.3f%%, mean ratio %.5f\n", 100.0 * worst, sumRatio / 256);
    EXPECT_NEAR(sumRatio / 256, 1.0, 0.005);  // σ(mean) ≈ 0.05 %
    EXPECT_LT(worst, 0.04);                   // σ(pixel) ≈ 0.8 % at 2048 paths
}

// Energy conservation through specular surfaces: a lossless sphere (ρs = 1: glass with exact
// Fresnel and total internal reflection, or a mirror) inside the white furnace leaves the
// uniform radiance field Le / (1 - ρ) unchanged, also in the pixels that look through it.
TEST(PathTracerAccuracy, LosslessSpheresInFurnaceConserveEnergy) {
    for (SpecularKind kind : {SpecularKind::Dielectric, SpecularKind::Mirror}) {
        Scene scene;
        int walls = addEmitter(scene, Vec3(0.5f), Vec3(1.0f));
        addInwardBox(scene, walls);
        Material glass;
        glass.name = "glass";
        glass.rhoS = Vec3(1.0f);
        glass.specular = kind;
        glass.ior = 1.5f;
        scene.materials.push_back(glass);
        Sphere sphere;
        sphere.centre = {0.0f, 0.0f, -0.3f};
        sphere.radius = 0.5f;
        sphere.material = 1;
        scene.spheres.push_back(sphere);
        setCamera(scene, {0.0f, 0.0f, 0.9f}, {0.0f, 0.0f, -0.3f}, {0, 1, 0}, 40.0f, 12,
                  12);  // the sphere fills the view
        Image img = render(scene, 768, 256);
        double mean = meanChannel(img, 0);
        std::printf("%s sphere in furnace: mean %.5f expected 2 (%+.3f%%)\n",
                    kind == SpecularKind::Dielectric ? "glass" : "mirror", mean, 100.0 * (mean / 2.0 - 1.0));
        EXPECT_NEAR(mean / 2.0, 1.0, 0.01);  // σ(mean) ≈ 0.1 %
    }
}

// Glossy and diffuse lobes together: a mixed floor (ρd 0.3, normalised Phong ρs 0.6, n 20)
// under a box whose other walls emit Le and reflect nothing. Seen at normal incidence both
// lobes lie wholly above the floor and the normalised lobe reflects exactly ρs, so
// L = (ρd + ρs) Le. Light sampling, BSDF sampling and their MIS weights all take part.
TEST(PathTracerAccuracy, GlossyAndDiffuseAlbedoAtNormalIncidence) {
    Scene scene;
    int lamp = addEmitter(scene, Vec3(0.0f), Vec3(2.0f));
    Material floor;
    floor.rhoD = Vec3(0.3f);
    floor.rhoS = Vec3(0.6f);
    floor.specular = SpecularKind::Glossy;
    floor.phongExponent = 20.0f;
    scene.materials.push_back(floor);
    addInwardBox(scene, lamp);
    scene.meshes[2].material = 1;  // the face at y = -1, looking up
    setCamera(scene, {0.0f, -0.5f, 0.0f}, {0.0f, -1.0f, 0.0f}, {0, 0, -1}, 1.0f, 8, 8);
    Image img = render(scene, 1024);
    double mean = meanChannel(img, 0);
    std::printf("glossy + diffuse floor: mean %.5f expected 1.8 (%+.3f%%)\n", mean, 100.0 * (mean / 1.8 - 1.0));
    EXPECT_NEAR(mean / 1.8, 1.0, 0.005);
}

// Fresnel: the exact formula at normal incidence is ((n-1)/(n+1))², at grazing incidence 1,
// and beyond the critical angle inside the denser medium total internal reflection.
TEST(PathTracerAccuracy, FresnelDielectric) {
    EXPECT_NEAR(fresnelDielectric(1.0f, 1.0f, 1.5f), 0.04f, 1e-6);
    EXPECT_NEAR(fresnelDielectric(1.0f, 1.5f, 1.0f), 0.04f, 1e-6);
    EXPECT_NEAR(fresnelDielectric(0.0f, 1.0f, 1.5f), 1.0f, 1e-6);
    float critical = std::sqrt(1.0f - 1.0f / (1.5f * 1.5f));  // cos of the critical angle
    EXPECT_EQ(fresnelDielectric(critical - 0.01f, 1.5f, 1.0f), 1.0f);
    EXPECT_LT(fresnelDielectric(critical + 0.01f, 1.5f, 1.0f), 1.0f);
    // 45° from air into glass: Rs = 0.0920, Rp = 0.00846 → 0.0502.
    EXPECT_NEAR(fresnelDielectric(std::cos(kPi / 4), 1.0f, 1.5f), 0.05023f, 1e-4);
}

// Motion blur: an emitting square (half-width 0.5) slides by 2 along x over the shutter. A
// point at x ∈ [-0.5, 0.5] sees it for τ ≤ (x + 0.5)/2, so a view symmetric about x = 0
// averages Le/4.
TEST(PathTracerAccuracy, MotionBlurAveragesOverTheShutter) {
    Scene scene;
    int lamp = addEmitter(scene, Vec3(0.0f), Vec3(1.0f));
    addQuad(scene, lamp, Vec3(0.0f), Vec3(0, 0, 1), 0.5f, 2.0f, Vec3(2.0f, 0.0f, 0.0f), Vec3(1, 0, 0));
    setCamera(scene, {0.0f, 0.0f, 2.0f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 20.0f, 8, 8);  // sees x ∈ ±0.35
    scene.camera.shutterOpen = 0.0f;
    scene.camera.shutterClose = 0.02f;
    Image img = render(scene, 512);
    double mean = meanChannel(img, 0);
    // Per-sample values are 0 or 1 with p ≈ 1/4: σ(mean) = sqrt(3/16 / 32768) = 0.0024.
    EXPECT_NEAR(mean, 0.25, 0.01);
    // Left to right the covered fraction (x + 0.5)/2 grows: the edge columns differ by ~0.15.
    double left = 0, right = 0;
    for (int y = 0; y < 8; ++y) {
        left += img.at(0, y).x / 8;
        right += img.at(7, y).x / 8;
    }
    EXPECT_GT(right - left, 0.10);
    scene.camera.shutterClose = 0.0f;  // an instantaneous shutter: the square at τ = 0 covers the view
    EXPECT_EQ(meanChannel(render(scene, 4), 0), 1.0);
}

// Depth of field: an emitting half-plane x < 0 at distance D, thin lens of radius a focused at
// distance f. A ray through the lens point (a lx, a ly) and the pinhole ray's point on the
// focus plane at x_f meets the emitter at x = x_f D/f + a lx (1 - D/f); lx is the x coordinate
// of a uniform point on the unit disk, P(lx < s) = 1/2 + (s sqrt(1-s²) + asin s)/π.
TEST(PathTracerAccuracy, ThinLensDepthOfField) {
    Scene scene;
    int lamp = addEmitter(scene, Vec3(0.0f), Vec3(1.0f));
    const float D = 4.0f;
    addQuad(scene, lamp, Vec3(-5.0f, 0.0f, -D), Vec3(0, 0, 1), 5.0f, 5.0f, Vec3(0.0f), Vec3(1, 0, 0));
    setCamera(scene, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, {0, 1, 0}, 10.0f, 16, 4);
    scene.camera.model = CameraModel::ThinLens;
    scene.camera.apertureRadius = 0.1f;
    scene.camera.focusDistance = 2.0f;  // the edge is out of focus: blur radius a |1 - D/f| = 0.1
    Image img = render(scene, 256);
    const Camera& cam = scene.camera;
    auto diskCdf = [](double s) {
        if (s <= -1) return 0.0;
        if (s >= 1) return 1.0;
        return 0.5 + (s * std::sqrt(1 - s * s) + std::asin(s)) / kPi;
    };
    // With D > f the factor (1 - D/f) is negative: lx (1 - D/f) < -x_f D/f ⇔ lx > s.
    const double k = cam.apertureRadius * (1.0 - D / cam.focusDistance);
    double worst = 0.0;
    for (int x = 0; x < 16; ++x) {
        double expected = 0.0;  // averaged over the pixel's width; every row has the same value
        for (int i = 0; i < 64; ++i) {
            Vec3 d = pinholeDirection(cam, x, 0, (i + 0.5f) / 64, 0.5f);
            double xf = d.x * cam.focusDistance / -d.z;
            expected += (1.0 - diskCdf((-xf * D / cam.focusDistance) / k)) / 64;
        }
        double measured = 0.0;
        for (int y = 0; y < 4; ++y) measured += img.at(x, y).x / 4;
        worst = std::max(worst, std::abs(measured - expected));
        EXPECT_NEAR(measured, expected, 0.035) << "column " << x;  // 1024 samples: σ ≤ 0.5/32 = 0.016
    }
    std::printf("depth of field: worst column error %.4f\n", worst);
    // In focus, the edge is sharp: columns left of centre are fully lit, right of it dark.
    scene.camera.focusDistance = D;
    Image sharp = render(scene, 16);
    EXPECT_EQ(sharp.at(6, 1).x, 1.0f);
    EXPECT_EQ(sharp.at(9, 1).x, 0.0f);
}

// MIS against BSDF sampling alone: two independent estimators of the same image must agree on
// a box with every material kind (diffuse walls, glossy floor, mirror and glass spheres) lit
// by a large area light. Compared over 4×4-pixel blocks and the whole image.
TEST(PathTracerAccuracy, MisAgreesWithBsdfSamplingAlone) {
    Scene scene;
    int white = addMaterial(scene, Vec3(0.7f));
    int red = addMaterial(scene, Vec3(0.6f, 0.1f, 0.1f));
    int lamp = addEmitter(scene, Vec3(0.0f), Vec3(2.0f));
    Material glossy;
    glossy.rhoD = Vec3(0.3f);
    glossy.rhoS = Vec3(0.5f);
    glossy.specular = SpecularKind::Glossy;
    glossy.phongExponent = 30.0f;
    scene.materials.push_back(glossy);  // 3
    Material mirror;
    mirror.rhoS = Vec3(0.9f);
    mirror.specular = SpecularKind::Mirror;
    scene.materials.push_back(mirror);  // 4
    Material glass;
    glass.rhoS = Vec3(1.0f);
    glass.specular = SpecularKind::Dielectric;
    scene.materials.push_back(glass);  // 5
    addInwardBox(scene, white);
    scene.meshes[0].material = red;                                             // x = -1 wall
    scene.meshes[2].material = 3;                                               // floor
    addQuad(scene, lamp, Vec3(0.0f, 0.99f, 0.0f), Vec3(0, -1, 0), 0.8f, 0.8f);  // large: BSDF sampling finds it
    Sphere a, b;
    a.centre = {-0.45f, -0.6f, -0.2f};
    a.radius = 0.4f;
    a.material = 4;
    b.centre = {0.45f, -0.6f, 0.2f};
    b.radius = 0.4f;
    b.material = 5;
    scene.spheres = {a, b};
    setCamera(scene, {0.0f, 0.0f, 0.99f}, {0.0f, -0.2f, 0.0f}, {0, 1, 0}, 80.0f, 16, 16);
    SceneGeometry geometry = SceneGeometry::build(scene);
    PathTracerSettings settings;
    settings.seed = 11;
    if (const char* seed = std::getenv("PHOTONCL_TEST_SEED")) settings.seed = std::strtoull(seed, nullptr, 10);
    settings.threads = 2;
    settings.samplesPerPixel = 512;
    if (const char* scale = std::getenv("PHOTONCL_TEST_SPP_SCALE")) settings.samplesPerPixel *= std::atoi(scale);
    Image mis = PathTracer(scene, geometry, settings).render().resolve();
    settings.lightSampling = false;
    settings.samplesPerPixel *= 4;
    settings.seed += 1000;
    Image bsdfOnly = PathTracer(scene, geometry, settings).render().resolve();

    // The bottom row of blocks holds the caustics under the spheres: light paths LS+D that both
    // estimators find by BSDF sampling alone, heavy-tailed at these sample counts.
    double worstBlock = 0.0, worstCausticBlock = 0.0;
    for (int by = 0; by < 4; ++by)
        for (int bx = 0; bx < 4; ++bx) {
            double sm = 0.0, sb = 0.0;
            for (int y = 4 * by; y < 4 * by + 4; ++y)
                for (int x = 4 * bx; x < 4 * bx + 4; ++x) {
                    sm += luminance(mis.at(x, y));
                    sb += luminance(bsdfOnly.at(x, y));
                }
            double& worst = by < 3 ? worstBlock : worstCausticBlock;
            worst = std::max(worst, std::abs(sm / sb - 1.0));
        }
    double total = meanChannel(mis, 0) / meanChannel(bsdfOnly, 0);
    std::printf("MIS vs BSDF-only: mean ratio %.5f, worst 4x4 block %.3f%% (caustic row %.3f%%)\n", total,
                100.0 * worstBlock, 100.0 * worstCausticBlock);
    // Pixels differ by ~5 % (σ, mostly the BSDF-only image): over seeds 1-6 the mean ratio stayed
    // within 1.2 %, blocks within 3.1 %, caustic blocks within 3.5 %.
    EXPECT_NEAR(total, 1.0, 0.02);
    EXPECT_LT(worstBlock, 0.06);
    EXPECT_LT(worstCausticBlock, 0.10);
}

// Same seed → the same film bits with 1 and 2 threads; shards by firstSample merge into the
// single-run film exactly; another seed changes it.
TEST(PathTracerAccuracy, DeterministicAcrossThreadsAndShards) {
    Scene scene;
    int white = addMaterial(scene, Vec3(0.7f));
    int red = addMaterial(scene, Vec3(0.6f, 0.1f, 0.1f));
    int lamp = addEmitter(scene, Vec3(0.0f), Vec3(10.0f));
    addInwardBox(scene, white);
    scene.meshes[0].material = red;
    addQuad(scene, lamp, Vec3(0.0f, 0.99f, 0.0f), Vec3(0, -1, 0), 0.3f, 0.3f);
    Material glass;
    glass.rhoS = Vec3(1.0f);
    glass.specular = SpecularKind::Dielectric;
    scene.materials.push_back(glass);
    Sphere s;
    s.centre = {0.3f, -0.6f, 0.0f};
    s.radius = 0.35f;
    s.material = 3;
    scene.spheres.push_back(s);
    setCamera(scene, {0.0f, 0.0f, 0.95f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 80.0f, 20, 14);
    SceneGeometry geometry = SceneGeometry::build(scene);
    PathTracerSettings settings;
    settings.samplesPerPixel = 4;
    settings.seed = 42;
    settings.threads = 1;
    Image one = PathTracer(scene, geometry, settings).render().resolve();
    settings.threads = 2;
    std::vector<double> progress;  // called under a lock: no synchronisation needed here
    settings.progress = [&](double f) { progress.push_back(f); };
    PathTracerStats stats;
    Image two = PathTracer(scene, geometry, settings).render(&stats).resolve();
    settings.progress = nullptr;
    EXPECT_EQ(one.rgb, two.rgb);
    ASSERT_EQ(progress.size(), 2u);  // one call per 16×16 tile: 20×14 pixels are two tiles
    EXPECT_EQ(progress.back(), 1.0);
    EXPECT_EQ(stats.samples, 20u * 14u * 4u);
    EXPECT_EQ(stats.discardedSamples, 0u);
    EXPECT_GT(stats.samplesPerSecond(), 0.0);

    settings.samplesPerPixel = 1;
    Film shards = PathTracer(scene, geometry, settings).render();
    settings.firstSample = 1;
    settings.samplesPerPixel = 3;
    shards.merge(PathTracer(scene, geometry, settings).render());
    Image merged = shards.resolve();
    for (size_t i = 0; i < one.rgb.size(); ++i) ASSERT_NEAR(merged.rgb[i], one.rgb[i], 1e-6f * (1 + one.rgb[i])) << i;

    settings.firstSample = 0;
    settings.samplesPerPixel = 4;
    settings.seed = 43;
    EXPECT_NE(PathTracer(scene, geometry, settings).render().resolve().rgb, one.rgb);
}
