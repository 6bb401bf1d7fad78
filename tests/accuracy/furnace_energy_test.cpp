// Energy through the photon renderer, per pixel against closed forms, for fg, direct and
// progressive (and the path tracer as a witness). Scenes are built here so that the answer is
// exact everywhere:
//
// 1. Glowing shell. A closed triangulated sphere whose walls both emit and reflect, in three
//    materials of different colour, albedo (diffuse, and diffuse + mirror) and emission, with a
//    lossless mirror ball and a lossless glass ball inside. If every material's emission is
//    Le = (1 − ρd − ρs) L, then L is a solution of the rendering equation everywhere
//    (L = Le + (ρd + ρs) L at a wall; a lossless ball shows L), so every pixel is L, per channel.
//    This is the unequal area lights (three emitters of different radiance and colour), mixed
//    surfaces and coloured albedo in one closed form.
// 2. Lamps inside a diffuse sphere (radius R, albedo ρ): a spot at the centre, and two unequal
//    point lights off-centre. A sphere's form factor from any patch to a point is dA/A, so the
//    light reflected by the walls irradiates every wall point equally: after the direct
//    irradiance E_d(x) = Σ I_i(θ) cosφ / r², the walls reflect ρΦ once, ρ²Φ twice …, and
//    L(x) = ρ/π (E_d(x) + ρΦ / (A (1 − ρ))), A = 4πR², Φ the lamps' total power.
// Not here: glossy walls (a normalised Phong lobe loses the part below the horizon, so its
// albedo depends on the angle and no uniform field solves the equation) and directional light
// (it cannot enter a closed room).
//
// The expected image averages the closed form over 8×8 points per pixel (the reference camera's
// rays, intersected with the sphere analytically). Renders are one seed at 32×32, compared in
// 4×4-pixel blocks (8×8 blocks) so that a block's noise is a few per cent: the mean within 1 %
// (measured within 0.55 % in every case) and the 99th percentile of the blocks' relative error
// per channel under 12 % (glowing shell) or 10 % (lamps). Measured: glowing shell fg 7.0 %,
// direct 8.2 %, progressive 5.2 %, path 2.0 %; spot 5.3 / 6.3 / 5.7 / 5.2 %; two points 1.6 /
// 5.8 / 4.1 / 2.6 %; the errors are noise (no pattern across the blocks: they change sign from
// block to block, and the lit blocks agree within 1 %).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <vector>

#include "accuracy/accuracy_common.h"
#include "common/prepared_render.h"
#include "common/test_scenes.h"
#include "reference/camera.h"
#include "scene/validate.h"

using namespace pcl;
using namespace pcl::accuracy;
using namespace pcl::test_scenes;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kBlock = 4;  // pixels are compared in kBlock × kBlock blocks

// An icosphere of the given radius about the origin, subdivided `levels` times, its triangles
// facing inwards (the room is seen from inside), split into meshes by `part(centroid)`.
void addInwardSphere(Scene& scene, float radius, int levels, const std::vector<int>& materials,
                     const std::function<int(Vec3)>& part) {
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    std::vector<Vec3> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    std::vector<uint32_t> f = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                               4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                               6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
    for (Vec3& p : v) p = normalize(p);
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
        auto midpoint = [&](uint32_t a, uint32_t b) {
            auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back(normalize(v[a] + v[b]));
            return mid[key] = uint32_t(v.size() - 1);
        };
        std::vector<uint32_t> g;
        for (size_t i = 0; i < f.size(); i += 3) {
            uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
            uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            g.insert(g.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        f = std::move(g);
    }
    std::vector<TriangleMesh> meshes(materials.size());
    for (size_t i = 0; i < f.size(); i += 3) {
        Vec3 p[3] = {v[f[i]] * radius, v[f[i + 1]] * radius, v[f[i + 2]] * radius};
        TriangleMesh& m = meshes[part((p[0] + p[1] + p[2]) / 3.0f)];
        // The icosahedron's faces wind outwards; reversed, their normals point at the centre.
        for (int k : {0, 2, 1}) {
            m.positions.push_back(p[k]);
            m.indices.push_back(uint32_t(m.positions.size() - 1));
        }
    }
    for (size_t i = 0; i < meshes.size(); ++i) {
        meshes[i].material = materials[i];
        meshes[i].name = "shell" + std::to_string(i);
        scene.meshes.push_back(meshes[i]);
        if (scene.materials[materials[i]].emits()) {
            Light l;
            l.type = LightType::Area;
            l.name = meshes[i].name;
            l.mesh = int(scene.meshes.size() - 1);
            scene.lights.push_back(l);
        }
    }
}

void setCamera(Scene& s, Vec3 position, Vec3 lookAt, float vfov, int width, int height) {
    s.camera.position = position;
    s.camera.lookAt = lookAt;
    s.camera.up = Vec3(0, 1, 0);
    s.camera.vfovDegrees = vfov;
    s.camera.width = width;
    s.camera.height = height;
}

// The closed form averaged over 8×8 points of each pixel: `radiance(x)` at the point x where the
// camera ray leaves the sphere of radius R about the origin (the camera is inside it).
Image expectedImage(const Scene& s, float R, const std::function<Vec3(Vec3)>& radiance) {
    RayCamera camera(s.camera);
    Image img(s.camera.width, s.camera.height);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            Vec3 sum(0.0f);
            for (int j = 0; j < 8; ++j)
                for (int i = 0; i < 8; ++i) {
                    CameraSample cs;
                    cs.filmX = (i + 0.5f) / 8;
                    cs.filmY = (j + 0.5f) / 8;
                    PclRay r = camera.generateRay(x, y, cs);
                    Vec3 o(r.ox, r.oy, r.oz), d(r.dx, r.dy, r.dz);
                    double b = double(dot(o, d)), c = double(dot(o, o)) - double(R) * R;
                    double t = -b + std::sqrt(b * b - c);  // c < 0: inside, the far root
                    sum = sum + radiance(o + d * float(t));
                }
            img.set(x, y, sum / 64.0f);
        }
    return img;
}

struct PixelErrors {
    double meanRatio = 0, p99 = 0, worst = 0;
};

PixelErrors pixelErrors(const Image& fullImg, const Image& fullExpected) {
    const Image img = boxDownsample(fullImg, kBlock), expected = boxDownsample(fullExpected, kBlock);
    std::vector<double> rel;
    double a = 0, b = 0;
    for (size_t i = 0; i < img.rgb.size(); ++i) {
        a += img.rgb[i];
        b += expected.rgb[i];
        rel.push_back(std::abs(img.rgb[i] / expected.rgb[i] - 1.0));
    }
    std::sort(rel.begin(), rel.end());
    return {a / b, rel[size_t(0.99 * (rel.size() - 1))], rel.back()};
}

// Every method against the expected image, in kBlock × kBlock blocks: the mean within 1 % and the
// 99th percentile of the blocks' relative errors (per channel) under `bound`.
void checkEveryMethod(const std::string& what, const Scene& scene, const Image& expected, double bound) {
    const auto p = test::prepare(scene);
    for (RenderMethod m : {RenderMethod::FinalGather, RenderMethod::DirectVisualisation, RenderMethod::Progressive,
                           RenderMethod::PathTracing}) {
        PhotonRenderSettings s;
        s.passes = m == RenderMethod::Progressive ? 16 : 4;
        s.gatherRays = 32;
        s.globalPhotons = 100000;
        s.causticPhotons = 100000;
        s.seed = 9;
        const Image img = test::renderImage(*p, m, s, 256, 2, what);
        ASSERT_TRUE(allFinite(img)) << what << " " << renderMethodName(m);
        const PixelErrors e = pixelErrors(img, expected);
        std::printf("[figure] %s, %s: mean ratio %.4f, %dx%d blocks, 99th percentile %.2f %% (bound %.0f %%), "
                    "worst %.2f %%\n",
                    what.c_str(), renderMethodName(m), e.meanRatio, kBlock, kBlock, 100 * e.p99, 100 * bound,
                    100 * e.worst);
        EXPECT_NEAR(e.meanRatio, 1.0, 0.01) << what << " " << renderMethodName(m);
        EXPECT_LT(e.p99, bound) << what << " " << renderMethodName(m);
    }
}

}  // namespace

TEST(FurnaceEnergy, GlowingShellWithLosslessBallsIsUniformInEveryMethod) {
    const Vec3 L(0.6f, 1.0f, 1.5f);  // the field, per channel
    Scene s;
    struct Wall {
        Vec3 rhoD, rhoS;
    };
    const Wall walls[3] = {{{0.5f, 0.3f, 0.2f}, Vec3(0.0f)},          // orange, diffuse
                           {{0.2f, 0.5f, 0.3f}, {0.3f, 0.2f, 0.5f}},  // green, diffuse + mirror
                           {{0.1f, 0.2f, 0.6f}, Vec3(0.0f)}};         // blue, diffuse
    std::vector<int> materials;
    for (const Wall& w : walls) {
        const Vec3 albedo = w.rhoD + w.rhoS;
        const Vec3 emission = (Vec3(1.0f) - albedo) * L;
        materials.push_back(
            addMaterial(s, w.rhoD, w.rhoS, w.rhoS.x > 0 ? SpecularKind::Mirror : SpecularKind::None, emission));
    }
    addInwardSphere(s, 1.0f, 3, materials, [](Vec3 c) { return c.y > 0.3f ? 0 : c.x > 0 ? 1 : 2; });
    addSphere(s, {-0.35f, -0.2f, -0.45f}, 0.25f, addMaterial(s, Vec3(0.0f), Vec3(1.0f), SpecularKind::Mirror));
    const int glass = addMaterial(s, Vec3(0.0f), Vec3(1.0f), SpecularKind::Dielectric);
    s.materials[glass].ior = 1.5f;
    addSphere(s, {0.3f, -0.25f, -0.4f}, 0.25f, glass);
    setCamera(s, {0, 0, 0.5f}, {0, -0.2f, -1}, 75.0f, 32, 32);
    validateScene(s);
    const Image expected = expectedImage(s, 1.0f, [&](Vec3) { return L; });
    checkEveryMethod("glowing shell", s, expected, 0.12);
}

TEST(FurnaceEnergy, LampsInsideADiffuseSphereMatchTheClosedForm) {
    const double rho = 0.6, R = 1.0, area = 4 * kPi * R * R;
    auto room = [&](Scene& s) {
        addSphere(s, {0, 0, 0}, float(R), addMaterial(s, Vec3(float(rho))));
        setCamera(s, {0, 0, 0.3f}, {0, -0.3f, -1}, 80.0f, 32, 32);
    };
    {  // a spot at the centre: full intensity inside 20°, smoothstep to zero at 45°
        Scene s;
        room(s);
        Light spot;
        spot.type = LightType::Spot;
        spot.name = "spot";
        spot.position = Vec3(0.0f);
        spot.direction = normalize(Vec3(0.2f, -0.5f, -1.0f));
        spot.intensity = Vec3(2.0f, 1.5f, 1.0f);
        spot.cosInner = std::cos(20.0 * kPi / 180);
        spot.cosOuter = std::cos(45.0 * kPi / 180);
        s.lights.push_back(spot);
        validateScene(s);
        const double power = 2 * kPi * ((1 - spot.cosInner) + (spot.cosInner - spot.cosOuter) / 2);  // per unit I
        const Image expected = expectedImage(s, float(R), [&](Vec3 x) {
            const double c = dot(normalize(x), spot.direction);
            const double t = std::clamp((c - spot.cosOuter) / (spot.cosInner - spot.cosOuter), 0.0, 1.0);
            const double falloff = t * t * (3 - 2 * t);  // r = R, cosφ = 1 at the wall
            const double indirect = rho * power / (area * (1 - rho));
            return spot.intensity * float(rho / kPi * (falloff + indirect));
        });
        checkEveryMethod("spot at the centre", s, expected, 0.10);
    }
    {  // two point lights of different colour and power, off-centre
        Scene s;
        room(s);
        Light a = pointLight({0.4f, 0.3f, -0.2f}), b = pointLight({-0.5f, -0.2f, 0.1f});
        a.intensity = Vec3(1.0f, 0.6f, 0.3f);
        b.intensity = Vec3(0.2f, 0.5f, 1.2f);
        s.lights = {a, b};
        validateScene(s);
        const Vec3 power = (a.intensity + b.intensity) * float(4 * kPi);
        const Image expected = expectedImage(s, float(R), [&](Vec3 x) {
            Vec3 direct(0.0f);
            for (const Light& l : s.lights) {
                const Vec3 d = l.position - x;
                const double r2 = dot(d, d), cosPhi = dot(normalize(d), normalize(x * -1.0f));
                direct = direct + l.intensity * float(cosPhi / r2);
            }
            return (direct + power * float(rho / (area * (1 - rho)))) * float(rho / kPi);
        });
        checkEveryMethod("two point lights", s, expected, 0.10);
    }
}
