// Caustics: light reaching a diffuse floor through glass (L S S D E, a glass
// ball) and from a mirror (L S D E), photon-mapped against the reference path tracer.
//
// What "the caustic's total power" means here, the same for both renderers: the floor's image
// with the specular object minus the floor's image with a black twin in its place (same shape,
// ρ = 0: the same shadow, no light through it), summed over the pixels where the camera sees
// the floor (the twin's albedo AOV reads the floor's ρ, and so do its 8 neighbours: a pixel on
// the object's silhouette can have all its few photon-renderer eye samples on the floor while
// the path tracer's hundreds of samples partly see the object). That difference is exactly the
// light that reaches the floor by way of the specular object: the caustic map's part in the
// photon renderer (plus the little that final gathering adds by way of the object), all of it
// in the path tracer. The light is an area light facing down, so the path tracer finds the
// caustic by BSDF sampling (with a point light it cannot). Same seed for the pair: paths that
// never touch the object are identical in both images and cancel exactly. The camera must see
// the whole caustic, away from the object's silhouette: a density estimate blurs the caustic by
// its search radius, and the path tracer samples a pixel differently from the photon renderer,
// so a sum over pixels that cuts through the caustic compares neither its power nor the same
// pixels.
#include "stability/stability_common.h"

#include <functional>
#include <random>

#include "check/on_device.h"
#include "pipeline/estimate.h"
#include "pipeline/photon_pass.h"

#include "reference/path_tracer.h"

using namespace pcl;
using namespace pcl::stability;

namespace {

// Floor (ρ 0.5) 3 × 3 at y = 0, an area light 0.6 × 0.6 at y = 1.5 facing down, the camera
// above and to the side; `object` adds the specular object (or its twin) with material m.
Scene causticStage(const std::function<void(Scene&, int)>& object, bool twin,
                   const std::function<void(Camera&)>& view = nullptr) {
    Scene s;
    const int floorM = test::addMaterial(s, Vec3(0.5f));
    int lightM = test::addMaterial(s, Vec3(0.0f));
    s.materials[lightM].emission = Vec3(10.0f);
    TriangleMesh floor, lamp;
    floor.material = floorM;
    test::addQuad(floor, Vec3(-1.5f, 0, -1.5f), Vec3(-1.5f, 0, 1.5f), Vec3(1.5f, 0, 1.5f), Vec3(1.5f, 0, -1.5f));
    lamp.material = lightM;
    test::addQuad(lamp, Vec3(-0.3f, 1.5f, -0.3f), Vec3(0.3f, 1.5f, -0.3f), Vec3(0.3f, 1.5f, 0.3f),
                  Vec3(-0.3f, 1.5f, 0.3f));  // normal −y
    s.meshes = {floor, lamp};
    Light l;
    l.type = LightType::Area;
    l.mesh = 1;
    s.lights.push_back(l);
    const int objectM = twin ? test::addMaterial(s, Vec3(0.0f))
                             : test::addMaterial(s, Vec3(0.0f), Vec3(1.0f), SpecularKind::Mirror);
    object(s, objectM);
    s.camera.position = Vec3(0.0f, 3.0f, -2.5f);
    s.camera.lookAt = Vec3(0.0f, 0.0f, 0.0f);
    s.camera.vfovDegrees = 55.0f;
    s.camera.width = s.camera.height = 32;
    if (view) view(s.camera);
    validateScene(s);
    return s;
}

struct CausticPower {
    double photon = 0, path = 0, causticAov = 0, directDiff = 0, indirectDiff = 0, emittedDiff = 0;
    size_t pixels = 0;
};

struct MeasureOptions {
    bool glass = false;
    std::function<void(Camera&)> view;  // the camera; none: causticStage's
    uint32_t passes = 2;                // photon renderer passes (2 × 2 eye samples each)
    int pathSamples = 512;              // path tracer samples per pixel
};

// The floor's pixels: the twin's albedo reads ρ = 0.5 there and at the 8 neighbours (inside the
// image), so no pixel on the object's silhouette counts.
std::vector<bool> floorPixels(const Image& albedo) {
    auto floor = [&](int x, int y) { return std::abs(albedo.at(x, y).x - 0.5f) <= 1e-4f; };
    std::vector<bool> mask(albedo.pixelCount(), false);
    for (int y = 0; y < albedo.height; ++y)
        for (int x = 0; x < albedo.width; ++x) {
            bool all = true;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx >= 0 && yy >= 0 && xx < albedo.width && yy < albedo.height && !floor(xx, yy)) all = false;
                }
            mask[size_t(y) * albedo.width + x] = all;
        }
    return mask;
}

CausticPower measure(const std::function<void(Scene&, int)>& object, const MeasureOptions& o) {
    const bool glass = o.glass;
    auto withObject = [&](bool twin) {
        Scene s = causticStage(object, twin, o.view);
        if (glass && !twin) {
            Material& m = s.materials.back();
            m.specular = SpecularKind::Dielectric;
            m.ior = 1.5f;
        }
        return prepare(s);
    };
    auto spec = withObject(false), black = withObject(true);
    PhotonRenderSettings rs;
    rs.passes = o.passes;
    rs.strata = 2;
    rs.globalPhotons = 50000;
    rs.causticPhotons = 200000;
    rs.gatherRays = 16;
    rs.aovs = true;
    rs.seed = 13;
    PhotonRenderResult a = render(*spec, rs), b = render(*black, rs);
    const Image ia = a.film.resolve(), ib = b.film.resolve(), ca = a.aovs.caustic.resolve();
    const std::vector<bool> mask = floorPixels(b.aovs.albedo.resolve());
    const Image da = a.aovs.direct.resolve(), db = b.aovs.direct.resolve(), na = a.aovs.indirect.resolve(),
                nb = b.aovs.indirect.resolve(), ea = a.aovs.emitted.resolve(), eb = b.aovs.emitted.resolve();
    expectFinite(a, ia, "photon, specular");
    expectFinite(b, ib, "photon, twin");
    PathTracerSettings pt;
    pt.samplesPerPixel = o.pathSamples;
    pt.seed = 4;
    pt.threads = 2;
    const Image pa = PathTracer(spec->scene, *spec->geometry, pt).render().resolve();
    const Image pb = PathTracer(black->scene, *black->geometry, pt).render().resolve();
    EXPECT_TRUE(allFinite(pa) && allFinite(pb));
    CausticPower c;
    for (int y = 0; y < ia.height; ++y)
        for (int x = 0; x < ia.width; ++x) {
            if (!mask[size_t(y) * ia.width + x]) continue;
            ++c.pixels;
            for (int k = 0; k < 3; ++k) {
                c.photon += ia.at(x, y)[k] - ib.at(x, y)[k];
                c.path += pa.at(x, y)[k] - pb.at(x, y)[k];
                c.causticAov += ca.at(x, y)[k];
                c.directDiff += da.at(x, y)[k] - db.at(x, y)[k];
                c.indirectDiff += na.at(x, y)[k] - nb.at(x, y)[k];
                c.emittedDiff += ea.at(x, y)[k] - eb.at(x, y)[k];
            }
        }
    return c;
}

void report(const char* what, const CausticPower& c) {
    std::printf("[figure] %s caustic power over %zu floor pixels: photon-mapped %.4f, path-traced %.4f, ratio %.4f "
                "(tolerance 3%%); of it caustic AOV %.4f, direct %+.4f, indirect %+.4f, emitted %+.4f\n",
                what, c.pixels, c.photon, c.path, c.photon / c.path, c.causticAov, c.directDiff, c.indirectDiff,
                c.emittedDiff);
}

}  // namespace

// A mirror wall (x = 0.6, facing −x) beside the lamp: the lamp's image lands on the floor.
TEST(Caustics, MirrorCausticPowerMatchesPathTracer) {
    CausticPower c = measure(
        [](Scene& s, int m) {
            TriangleMesh mirror;
            mirror.material = m;
            test::addQuad(mirror, Vec3(0.6f, 0.0f, -0.8f), Vec3(0.6f, 0.0f, 0.8f), Vec3(0.6f, 1.4f, 0.8f),
                          Vec3(0.6f, 1.4f, -0.8f));
            s.meshes.push_back(mirror);
        },
        MeasureOptions{});
    report("mirror", c);
    ASSERT_GT(c.pixels, 250u);
    ASSERT_GT(c.path, 0.0);
    EXPECT_NEAR(c.photon / c.path, 1.0, 0.03);
}

// A glass ball (ior 1.5, radius 0.35) under the lamp: refracted twice, focused on the floor
// (LSSDE). Its caustic lies under the ball (radius ≈ 0.24 about the origin), so the camera looks
// from low (22° above the floor) and sees all of it below the ball. From causticStage's camera
// (above, to the side) the caustic's bright centre sat on the ball's lower silhouette and this
// test read 1.21 × the path tracer: the floor pixels held only the caustic's edge, 4-8
// silhouette pixels carried most of the sum, and whether they counted depended on where the 8
// jittered eye samples of a pixel fell (the path tracer's sum over one seed's mask 5.1, over
// another's 9.0-10.7; with silhouette pixels left out 1.4-1.6 against the photon renderer's
// 1.5-1.7). Seen whole, the caustic AOV sums to 1.02 × the caustic map's photons projected onto
// the same pixels (the k-nearest estimate's small excess; 1.007 × integrated over the whole
// floor), and over seeds 13-16 / 4-7 the ratio below read 1.009-1.021.
TEST(Caustics, GlassCausticPowerMatchesPathTracer) {
    MeasureOptions o;
    o.glass = true;
    o.view = [](Camera& c) {
        c.position = Vec3(0.0f, 0.9f, -2.2f);
        c.lookAt = Vec3(0.0f, 0.05f, 0.0f);
        c.vfovDegrees = 30.0f;
        c.width = c.height = 48;
    };
    o.passes = 4;
    o.pathSamples = 2048;
    CausticPower c = measure(
        [](Scene& s, int m) {
            Sphere ball;
            ball.centre = Vec3(0.0f, 0.5f, 0.0f);
            ball.radius = 0.35f;
            ball.material = m;
            s.spheres.push_back(ball);
        },
        o);
    report("glass ball", c);
    ASSERT_GT(c.pixels, 1000u);
    ASSERT_GT(c.path, 0.0);
    EXPECT_NEAR(c.photon / c.path, 1.0, 0.03);
}

namespace {

// Fresnel reflectance of a smooth dielectric, unpolarised (written here, not the project's).
double fresnel(double cosI, double etaI, double etaT) {
    const double sinT = etaI / etaT * std::sqrt(std::max(0.0, 1.0 - cosI * cosI));
    if (sinT >= 1.0) return 1.0;
    const double cosT = std::sqrt(1.0 - sinT * sinT);
    const double rs = (etaI * cosI - etaT * cosT) / (etaI * cosI + etaT * cosT);
    const double rp = (etaT * cosI - etaI * cosT) / (etaT * cosI + etaI * cosT);
    return 0.5 * (rs * rs + rp * rp);
}

// The power (per channel) the glass ball sends to the floor, by an independent Monte Carlo on
// the host in double precision: lamp points uniform, cosine directions, the ball's surfaces
// with Fresnel reflection / refraction chosen by probability, up to 64 events.
double glassCausticPowerMonteCarlo(int paths, uint32_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double L = 10.0, area = 0.36, power = L * M_PI * area, R = 0.35, cy = 0.5, ior = 1.5;
    double landed = 0.0;
    for (int i = 0; i < paths; ++i) {
        double o[3] = {-0.3 + 0.6 * u(rng), 1.5, -0.3 + 0.6 * u(rng)};
        const double r1 = u(rng), r2 = u(rng), rr = std::sqrt(r1), phi = 2 * M_PI * r2;
        double d[3] = {rr * std::cos(phi), -std::sqrt(std::max(0.0, 1 - r1)), rr * std::sin(phi)};
        bool touched = false, inside = false;
        for (int event = 0; event < 64; ++event) {
            // The ball: |o + t d − c|² = R².
            const double oc[3] = {o[0], o[1] - cy, o[2]};
            const double b = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
            const double c = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - R * R;
            const double disc = b * b - c;
            double t = -1;
            if (disc > 0) {
                const double s = std::sqrt(disc);
                t = -b - s > 1e-9 ? -b - s : (-b + s > 1e-9 ? -b + s : -1);
            }
            if (t < 0) {
                // Leaves the ball's reach: the floor (y = 0, |x|, |z| ≤ 1.5) if going down, the
                // lamp's black back or the sky if going up.
                if (touched && d[1] < 0) {
                    const double tf = -o[1] / d[1], x = o[0] + tf * d[0], z = o[2] + tf * d[2];
                    if (std::abs(x) <= 1.5 && std::abs(z) <= 1.5) landed += 1.0;
                }
                break;
            }
            if (!touched) {
                // Before the ball a path may end on the floor as direct light: not a caustic.
                touched = true;
            }
            double p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
            double n[3] = {p[0] / R, (p[1] - cy) / R, p[2] / R};
            double cosI = -(n[0] * d[0] + n[1] * d[1] + n[2] * d[2]);
            if (cosI < 0) cosI = -cosI, n[0] = -n[0], n[1] = -n[1], n[2] = -n[2];
            const double etaI = inside ? ior : 1.0, etaT = inside ? 1.0 : ior;
            const double F = fresnel(cosI, etaI, etaT);
            if (u(rng) < F) {
                for (int k = 0; k < 3; ++k) d[k] += 2 * cosI * n[k];
            } else {
                const double eta = etaI / etaT, cosT = std::sqrt(1 - eta * eta * (1 - cosI * cosI));
                for (int k = 0; k < 3; ++k) d[k] = eta * d[k] + (eta * cosI - cosT) * n[k];
                inside = !inside;
            }
            for (int k = 0; k < 3; ++k) o[k] = p[k];
        }
    }
    return power * landed / paths;
}

// The stage with a glass ball (η 1.5, radius 0.35 at height 0.5: glassCausticPowerMonteCarlo's).
Scene glassBallStage() {
    Scene s = causticStage(
        [](Scene& sc, int m) {
            Sphere ball;
            ball.centre = Vec3(0.0f, 0.5f, 0.0f);
            ball.radius = 0.35f;
            ball.material = m;
            sc.spheres.push_back(ball);
        },
        false);
    s.materials.back().specular = SpecularKind::Dielectric;
    s.materials.back().ior = 1.5f;
    return s;
}

}  // namespace

// The photon pass's side of the glass caustic on its own: the caustic map's stored power on the
// floor (Σ decoded photon power) against the host Monte Carlo above (2M paths: ±0.3 %): within
// 3 %. This isolates the photon pass from the image comparison with the path tracer.
TEST(Caustics, GlassCausticMapPowerMatchesIndependentMonteCarlo) {
    Scene s = glassBallStage();
    auto p = prepare(s);
    PhotonPassOptions po;
    po.globalPhotons = 1000;
    po.causticPhotons = 400000;
    po.seed = 53;
    PhotonMaps maps = runPhotonPass(test::testDevice(), *p->geometry, p->buffers, po);
    double stored = 0.0;
    for (const PclPhoton& ph : maps.caustic) stored += test::decodedPower(ph);
    const double expected = glassCausticPowerMonteCarlo(2000000, 59);
    std::printf("[figure] glass ball caustic map power %.4f W (%zu photons) vs host Monte Carlo %.4f W: ratio %.4f "
                "(tolerance 3%%)\n",
                stored, maps.caustic.size(), expected, stored / expected);
    EXPECT_NEAR(stored / expected, 1.0, 0.03);
}

// The eye side's reading of the same caustic on its own: the caustic estimate (k = 50, cone, the
// renderer's r_max = 5 % of the bounds' diagonal) on a 1 cm grid over the whole floor, integrated,
// against the map's stored power: measured 1.014 × (1.007 × over the central 2.4 m square, where
// the box filter read 1.028 × and k = 10 with the cone 1.024 ×; the rest is the sparse tail of
// light reflected off the ball). The k-nearest estimate neither loses nor makes this caustic's
// power beyond the 3 %.
TEST(Caustics, GlassCausticEstimateIntegratesToMapPower) {
    Scene s = glassBallStage();
    auto p = prepare(s);
    PhotonPassOptions po;
    po.globalPhotons = 1000;
    po.causticPhotons = 200000;
    po.seed = 13;
    po.buildGlobal = false;
    PhotonMaps maps = runPhotonPass(test::testDevice(), *p->geometry, p->buffers, po);
    double stored = 0.0;
    for (const PclPhoton& ph : maps.caustic) stored += test::decodedPower(ph);
    const float rMax = 0.05f * length(p->geometry->bounds().extent());
    const double h = 0.01;
    const int n = 300;  // the floor is 3 × 3
    std::vector<PclEstimateQuery> queries;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            PclEstimateQuery q{};
            q.x = float(-1.5 + (i + 0.5) * h);
            q.z = float(-1.5 + (j + 0.5) * h);
            q.ny = 1.0f;
            q.maxRadius2 = rMax * rMax;
            q.k = 50;
            queries.push_back(q);
        }
    EstimateResult r = estimateOnDevice(test::testDevice(), maps.caustic, queries, EstimateSettings{}, nullptr);
    double integral = 0.0;
    for (const PclEstimate& e : r.values) integral += (double(e.r) + e.g + e.b) / 3.0 * h * h;
    std::printf("[figure] glass ball caustic estimate integrated over the floor %.4f W vs the map's %.4f W "
                "(%zu photons): ratio %.4f (tolerance 3%%)\n",
                integral, stored, maps.caustic.size(), integral / stored);
    ASSERT_GT(stored, 0.0);
    EXPECT_NEAR(integral / stored, 1.0, 0.03);
}
