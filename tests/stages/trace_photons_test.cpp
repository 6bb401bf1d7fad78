// trace_photons (kernels/trace_photons.cl) with emit and deposit around it: properties with
// analytic answers, no twin needed. A closed grey diffuse box of albedo ρ lit by a point light:
// every photon lands first on a wall and the records per path average 1/(1 - ρ) (Jensen's
// roulette keeps a grey photon's power, so every record carries Φ/N); maximum depth is counted;
// a mirror above a diffuse floor gives the image-source caustic flux, with and without
// projection maps; caustic photons bounce off the mirror lobe of a mixed floor and deposit on
// it (image-source answers again); glass never absorbs; records decode to points on the surfaces.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "check/on_device.h"
#include "device_fixture.h"
#include "photon_test_scenes.h"
#include "pipeline/emit.h"
#include "pipeline/photon_pass.h"
#include "pipeline/trace_photons.h"
#include "prep/photon_allocation.h"
#include "prep/projection_map.h"
#include "shared/sampling.h"

namespace pcl {
namespace {

constexpr uint32_t kPhotons = 100000;

test::BuiltScene greyBox(float rho) {
    Scene s;
    int m = test::addMaterial(s, Vec3(rho));
    s.meshes.push_back(test::closedBox(1.0f, m));
    s.lights.push_back(test::pointLight(Vec3(0.1f, 0.2f, -0.15f), Vec3(1.0f)));
    return test::build(s);
}

PhotonMaps globalOnly(const test::BuiltScene& b, uint32_t photons, uint32_t maxDepth = 64, uint32_t batch = 0) {
    PhotonPassOptions o;
    o.globalPhotons = photons;
    o.buildCaustic = false;
    o.maxDepth = maxDepth;
    o.batchSize = batch;
    o.seed = 11;
    return runPhotonPass(test::testDevice(), b.geometry, b.buffers, o);
}

uint32_t bounceOf(const PclPhoton& p) { return (p.packed >> PCL_PHOTON_BOUNCE_SHIFT) & 0xFFu; }
uint32_t flagsOf(const PclPhoton& p) { return p.packed & 0xFF000000u; }

TEST(TracePhotons, ClosedDiffuseBoxDepositsPhiAtFirstHitsAndPhiOverOneMinusRhoInAll) {
    const float rho = 0.5f;
    test::BuiltScene b = greyBox(rho);
    PhotonMaps maps = globalOnly(b, kPhotons, 255);
    const PhotonPassKindStats& s = maps.stats.global;
    std::printf("%s", maps.stats.summary().c_str());
    EXPECT_EQ(s.emitted, kPhotons);
    EXPECT_LE(s.escaped, kPhotons / 10000) << "photons leaked out of a closed box";
    EXPECT_EQ(s.escaped + s.absorbed + s.maxDepth, kPhotons);
    ASSERT_EQ(maps.global.size(), s.deposits);

    size_t firstHits = 0;
    const uint32_t rgbe = maps.global.empty() ? 0 : maps.global[0].rgbe;
    for (const PclPhoton& p : maps.global) {
        // On a wall of the box.
        float m = std::max(std::fabs(p.x), std::max(std::fabs(p.y), std::fabs(p.z)));
        ASSERT_NEAR(m, 1.0f, 1e-5f);
        // A grey photon keeps its power through roulette: every record carries Φ/N.
        ASSERT_EQ(p.rgbe, rgbe);
        uint32_t bounce = bounceOf(p);
        if (bounce == 0) {
            ++firstHits;
            EXPECT_EQ(flagsOf(p), 0u);
        } else {
            EXPECT_EQ(flagsOf(p), PCL_PHOTON_AFTER_DIFFUSE);
        }
        // The incoming direction points back into the box, off the wall it lies on.
        PclV3 w = photon_dir_decode(p.packed);
        float inward = std::fabs(p.x) == m ? -p.x * w.x : std::fabs(p.y) == m ? -p.y * w.y : -p.z * w.z;
        EXPECT_GT(inward, -0.03f);
    }
    // Flux at first hits: Φ (every photon hits a wall first).
    EXPECT_GE(firstHits, kPhotons - kPhotons / 10000);
    EXPECT_LE(firstHits, kPhotons);
    double perPhoton = test::decodedPower(maps.global[0]);
    double phi = scalarPower(b.buffers.lights[0]);
    EXPECT_NEAR(perPhoton * kPhotons, phi, phi / 128.0);  // RGBE keeps 8 bits
    // All bounces: Φ/(1 - ρ). Records per path are geometric: mean 1/(1-ρ), variance ρ/(1-ρ)².
    double mean = double(maps.global.size()) / kPhotons;
    double se = std::sqrt(rho / ((1 - rho) * (1 - rho)) / kPhotons);
    std::printf("records per path %.5f, expected %.5f ± %.5f (1 se)\n", mean, 1 / (1 - rho), se);
    EXPECT_NEAR(mean, 1.0 / (1.0 - rho), 3.0 * se);
}

TEST(TracePhotons, MaximumDepthEndsPathsAndIsCounted) {
    const float rho = 0.9f;
    const uint32_t depth = 3;
    test::BuiltScene b = greyBox(rho);
    PhotonMaps maps = globalOnly(b, kPhotons, depth);
    const PhotonPassKindStats& s = maps.stats.global;
    // A path reaches the cap when it survives roulette at hits 1..3: probability ρ³.
    double p = std::pow(rho, depth);
    EXPECT_NEAR(double(s.maxDepth), kPhotons * p, 5.0 * std::sqrt(kPhotons * p * (1 - p)));
    EXPECT_EQ(s.escaped + s.absorbed + s.maxDepth, kPhotons);
    for (const PclPhoton& ph : maps.global) ASSERT_LT(bounceOf(ph), depth);
    // Every path deposits once per hit: maxDepth paths deposit exactly `depth` records.
    EXPECT_GE(maps.global.size(), size_t(s.maxDepth) * depth);

    // The per-path view: ends carry the bounce at which the path stopped.
    std::vector<uint32_t> first = lightFirstPhoton(b.buffers, 20000, PCL_PASS_GLOBAL);
    PclPhotonParams params = makePhotonParams(b.geometry, b.buffers, PCL_PASS_GLOBAL, 5, depth, 0, first.back());
    auto rays = emitOnDevice(test::testDevice(), b.geometry, b.buffers, first, params);
    PhotonTraceResult t = tracePhotonsOnDevice(test::testDevice(), b.geometry, b.buffers, rays, params);
    ASSERT_EQ(t.slotsPerPath, depth);
    size_t capped = 0;
    for (size_t i = 0; i < t.ends.size(); ++i) {
        uint32_t bounce = t.ends[i] & 0xFFu, cause = t.ends[i] >> 8;
        ASSERT_GE(bounce, 1u);
        ASSERT_LE(bounce, depth);
        if (cause == PCL_END_MAX_DEPTH) {
            ++capped;
            EXPECT_EQ(bounce, depth);
            EXPECT_EQ(t.counts[i], depth);
        } else if (cause == PCL_END_ABSORBED) {
            EXPECT_EQ(t.counts[i], bounce);  // one record per hit, the last at the absorbing hit
        }
        for (uint32_t k = 0; k < t.counts[i]; ++k) EXPECT_EQ(bounceOf(t.slots[i * depth + k]), k);
    }
    EXPECT_GT(capped, 0u);
}

// Floor y = 0 (diffuse), a downward mirror square of half-size 0.5 at y = 2, a point light at
// y = 1 between them. Caustic flux (image source): Φ ρs Ω/(4π), Ω the mirror's solid angle.
test::BuiltScene mirrorAboveFloor(float rhoS) {
    Scene s;
    int floorM = test::addMaterial(s, Vec3(0.5f));
    int mirrorM = test::addMaterial(s, Vec3(0.0f), Vec3(rhoS), SpecularKind::Mirror);
    TriangleMesh floor;
    floor.material = floorM;
    test::addQuad(floor, Vec3(-50, 0, -50), Vec3(-50, 0, 50), Vec3(50, 0, 50), Vec3(50, 0, -50));
    s.meshes.push_back(floor);
    TriangleMesh mirror;
    mirror.material = mirrorM;
    test::addQuad(mirror, Vec3(-0.5f, 2, -0.5f), Vec3(0.5f, 2, -0.5f), Vec3(0.5f, 2, 0.5f), Vec3(-0.5f, 2, 0.5f));
    s.meshes.push_back(mirror);
    s.lights.push_back(test::pointLight(Vec3(0, 1, 0), Vec3(1.0f)));
    return test::build(s);
}

PhotonMaps causticOnly(const test::BuiltScene& b, uint32_t photons, uint64_t seed = 3) {
    PhotonPassOptions o;
    o.buildGlobal = false;
    o.causticPhotons = photons;
    o.seed = seed;
    return runPhotonPass(test::testDevice(), b.geometry, b.buffers, o);
}

double mapFlux(const std::vector<PclPhoton>& m) {
    double f = 0;
    for (const PclPhoton& p : m) f += test::decodedPower(p);
    return f;
}

TEST(TracePhotons, MirrorAboveFloorGivesTheImageSourceCausticFlux) {
    const float rhoS = 0.8f;
    test::BuiltScene b = mirrorAboveFloor(rhoS);
    const double phi = scalarPower(b.buffers.lights[0]);
    const double omega = 4.0 * std::atan(0.25 / std::sqrt(1.5));  // 4 atan(ab / (d √(a²+b²+d²)))
    const double p = rhoS * omega / (4.0 * 3.14159265358979323846);
    const double want = phi * p;

    // Unrestricted emission: every projection cell marked.
    test::markAllProjectionCells(b.buffers);
    PhotonMaps all = causticOnly(b, kPhotons);
    for (const PclPhoton& ph : all.caustic) {
        ASSERT_EQ(flagsOf(ph), PCL_PHOTON_CAUSTIC | PCL_PHOTON_AFTER_SPECULAR);
        ASSERT_EQ(bounceOf(ph), 1u);
        ASSERT_NEAR(ph.y, 0.0f, 1e-5f);
        ASSERT_LE(std::fabs(ph.x), 1.5f + 1e-4f);  // the image source at y = 3 through the mirror
    }
    EXPECT_EQ(all.stats.caustic.stored, all.caustic.size());
    double se = phi * std::sqrt(p * (1 - p) / kPhotons);
    double got = mapFlux(all.caustic);
    std::printf("caustic flux, all cells: %.6f, image source %.6f ± %.6f (1 se)\n", got, want, se);
    EXPECT_NEAR(got, want, 3.0 * se + want / 128.0);

    // Projection maps: photons only towards the mirror, flux scaled by the marked fraction.
    test::BuiltScene pm = mirrorAboveFloor(rhoS);
    buildProjectionMaps(pm.scene, pm.geometry, pm.buffers);
    ASSERT_GT(pm.buffers.lights[0].projCount, 0u);
    ASSERT_LT(pm.buffers.lights[0].projCount, PCL_PROJ_GRID * PCL_PROJ_GRID);
    PhotonMaps restricted = causticOnly(pm, kPhotons);
    double f = projectionFraction(pm.buffers.lights[0]);
    double pr = p / f;  // the chance a restricted photon makes a caustic
    double seR = phi * f * std::sqrt(pr * (1 - pr) / kPhotons);
    double gotR = mapFlux(restricted.caustic);
    std::printf("caustic flux, projection map (f = %.4f): %.6f ± %.6f; %zu records vs %zu\n", f, gotR, seR,
                restricted.caustic.size(), all.caustic.size());
    EXPECT_NEAR(gotR, want, 3.0 * std::sqrt(se * se + seR * seR) + want / 128.0);
    EXPECT_GT(restricted.caustic.size(), 3 * all.caustic.size());
}

// LS+D through a mixed surface (kernels/README.md, trace_photons step 1): a point light of
// power Φ at (0, 1, 0) over a mixed floor y = 0 of half-size 4 (ρd 0.4, mirror ρs 0.5), a pure
// mirror square of half-size 0.5 at y = 2 facing down (ρs 0.8), and a diffuse ceiling y = 3 of
// half-size 20 (large enough to catch every ray the floor reflects: from the image source at
// y = −1 through the floor's corner (4, 0, 4) a ray meets y = 3 at (16, 3, 16)). Grey surfaces
// keep Φ/N per photon through roulette, so every record carries Φ/N and the flux is
// Φ × (the probability of the path):
//  * ceiling records of bounce 1 (light → floor, specular lobe → ceiling): the image-source
//    answer Φ ρs_floor (Ω_floor − Ω_blocked)/(4π), Ω_floor the floor's solid angle from the light
//    and Ω_blocked the mirror's seen from the image source (0, −1, 0) (those rays meet the
//    mirror's underside before the ceiling);
//  * floor records of bounce 1 (light → mirror → mixed floor): Φ ρs_mirror Ω_mirror/(4π), the
//    floor catching every ray (image source (0, 3, 0): half-extent 1.5 at y = 0).
// Ω of a rectangle of half-sides a, b seen on axis from distance d: 4 atan(ab/(d √(a²+b²+d²))).
// A path light → mirror → floor (deposit, specular) → ceiling (deposit) deposits twice.
TEST(TracePhotons, CausticPhotonsBounceOffTheSpecularLobeOfAMixedSurface) {
    const float rhoDFloor = 0.4f, rhoSFloor = 0.5f, rhoSMirror = 0.8f;
    Scene s;
    int floorM = test::addMaterial(s, Vec3(rhoDFloor), Vec3(rhoSFloor), SpecularKind::Mirror);
    int mirrorM = test::addMaterial(s, Vec3(0.0f), Vec3(rhoSMirror), SpecularKind::Mirror);
    int ceilingM = test::addMaterial(s, Vec3(0.5f));
    TriangleMesh floor, mirror, ceiling;
    floor.material = floorM;
    test::addQuad(floor, Vec3(-4, 0, -4), Vec3(-4, 0, 4), Vec3(4, 0, 4), Vec3(4, 0, -4));
    mirror.material = mirrorM;
    test::addQuad(mirror, Vec3(-0.5f, 2, -0.5f), Vec3(0.5f, 2, -0.5f), Vec3(0.5f, 2, 0.5f), Vec3(-0.5f, 2, 0.5f));
    ceiling.material = ceilingM;
    test::addQuad(ceiling, Vec3(-20, 3, -20), Vec3(20, 3, -20), Vec3(20, 3, 20), Vec3(-20, 3, 20));
    s.meshes = {floor, mirror, ceiling};
    s.lights.push_back(test::pointLight(Vec3(0, 1, 0), Vec3(1.0f)));
    test::BuiltScene b = test::build(s);
    test::markAllProjectionCells(b.buffers);  // unrestricted emission: f = 1
    const uint32_t N = 200000;
    const double phi = double(N) / 1024.0;  // Φ/N = 2⁻¹⁰: exact in RGBE
    for (int c = 0; c < 3; ++c) b.buffers.lights[0].power[c] = float(phi);

    std::vector<uint32_t> first = lightFirstPhoton(b.buffers, N, PCL_PASS_CAUSTIC);
    ASSERT_EQ(first.back(), N);
    const uint32_t depth = 8;  // slots: N × 8 × 20 bytes
    PclPhotonParams params = makePhotonParams(b.geometry, b.buffers, PCL_PASS_CAUSTIC, 21, depth, 0, N);
    auto rays = emitOnDevice(test::testDevice(), b.geometry, b.buffers, first, params);
    PhotonTraceResult t = tracePhotonsOnDevice(test::testDevice(), b.geometry, b.buffers, rays, params);
    ASSERT_EQ(t.slotsPerPath, depth);

    const double perPhoton = phi / N;
    size_t ceilingHits = 0, floorHits = 0, twice = 0, stored = 0, records = 0;
    for (uint32_t i = 0; i < N; ++i) {
        ASSERT_LE(t.counts[i], depth);
        twice += t.counts[i] >= 2;
        records += t.counts[i];
        stored += (t.ends[i] >> 8) == PCL_END_STORED;
        for (uint32_t k = 0; k < t.counts[i]; ++k) {
            const PclPhoton& ph = t.slots[size_t(i) * depth + k];
            ASSERT_EQ(flagsOf(ph), PCL_PHOTON_CAUSTIC | PCL_PHOTON_AFTER_SPECULAR);
            ASSERT_EQ(test::decodedPower(ph), perPhoton);
            ASSERT_GE(bounceOf(ph), 1u);
            const bool onFloor = std::fabs(ph.y) < 1e-5f, onCeiling = std::fabs(ph.y - 3.0f) < 1e-5f;
            ASSERT_TRUE(onFloor || onCeiling) << ph.x << " " << ph.y << " " << ph.z;  // never on the mirror
            if (bounceOf(ph) != 1u) continue;
            if (onCeiling) ++ceilingHits;
            else ++floorHits;
        }
    }
    const double fourPi = 4.0 * 3.14159265358979323846;
    auto omega = [](double a, double bb, double d) {
        return 4.0 * std::atan(a * bb / (d * std::sqrt(a * a + bb * bb + d * d)));
    };
    const double pCeiling = rhoSFloor * (omega(4, 4, 1) - omega(0.5, 0.5, 3)) / fourPi;
    const double pFloor = rhoSMirror * omega(0.5, 0.5, 1) / fourPi;
    const double gotC = ceilingHits * perPhoton, wantC = phi * pCeiling,
                 seC = phi * std::sqrt(pCeiling * (1 - pCeiling) / N);
    const double gotF = floorHits * perPhoton, wantF = phi * pFloor, seF = phi * std::sqrt(pFloor * (1 - pFloor) / N);
    std::printf("[mixed caustic] N %u, Phi %.4f W: ceiling via the floor's mirror lobe %.5f W (image source %.5f, "
                "SE %.5f, %+.2f SE); floor via the mirror %.5f W (image source %.5f, SE %.5f, %+.2f SE); "
                "%zu records, %zu paths deposit twice or more, %zu end STORED\n",
                N, phi, gotC, wantC, seC, (gotC - wantC) / seC, gotF, wantF, seF, (gotF - wantF) / seF, records, twice,
                stored);
    EXPECT_NEAR(gotC, wantC, 3.0 * seC);
    EXPECT_NEAR(gotF, wantF, 3.0 * seF);
    EXPECT_LT(seC, 0.01 * wantC);
    EXPECT_LT(seF, 0.03 * wantF);
    // light → mirror → floor (deposit, mirror lobe) → ceiling (deposit): about N pFloor ρs_floor.
    EXPECT_GT(twice, size_t(0.5 * N * pFloor * rhoSFloor));
    EXPECT_LE(stored, N);
    EXPECT_GT(records, stored);  // some paths deposited and went on
}

// A glass sphere (ρs = 1) over a diffuse floor: the dielectric reflects or refracts, never
// absorbs, so a caustic path is absorbed only at a first hit on the floor.
TEST(TracePhotons, GlassNeverAbsorbsAndCausticsLandOnTheFloor) {
    Scene s;
    int floorM = test::addMaterial(s, Vec3(0.5f));
    int glass = test::addMaterial(s, Vec3(0.0f), Vec3(1.0f), SpecularKind::Dielectric, 0.0f, 1.5f);
    TriangleMesh floor;
    floor.material = floorM;
    test::addQuad(floor, Vec3(-20, 0, -20), Vec3(-20, 0, 20), Vec3(20, 0, 20), Vec3(20, 0, -20));
    s.meshes.push_back(floor);
    Sphere sp;
    sp.centre = Vec3(0, 1, 0);
    sp.radius = 0.5f;
    sp.material = glass;
    s.spheres.push_back(sp);
    s.lights.push_back(test::pointLight(Vec3(0, 3, 0), Vec3(1.0f)));
    test::BuiltScene b = test::build(s);
    test::markAllProjectionCells(b.buffers);

    std::vector<uint32_t> first = lightFirstPhoton(b.buffers, kPhotons, PCL_PASS_CAUSTIC);
    PclPhotonParams params = makePhotonParams(b.geometry, b.buffers, PCL_PASS_CAUSTIC, 9, 64, 0, first.back());
    auto rays = emitOnDevice(test::testDevice(), b.geometry, b.buffers, first, params);
    PhotonTraceResult t = tracePhotonsOnDevice(test::testDevice(), b.geometry, b.buffers, rays, params);
    ASSERT_EQ(t.slotsPerPath, 64u);  // maxDepth, as in a global pass
    size_t stored = 0, refracted = 0;
    const uint32_t emittedRgbe = photon_rgbe_encode(rays[0].power[0], rays[0].power[1], rays[0].power[2]);
    for (size_t i = 0; i < t.ends.size(); ++i) {
        uint32_t bounce = t.ends[i] & 0xFFu, cause = t.ends[i] >> 8;
        if (cause == PCL_END_ABSORBED) {
            EXPECT_EQ(bounce, 1u) << "path " << i;
        }
        if (cause == PCL_END_STORED) {
            ASSERT_EQ(t.counts[i], 1u);  // the floor is purely diffuse: the path ends there
            const PclPhoton& ph = t.slots[i * t.slotsPerPath];
            ++stored;
            refracted += bounceOf(ph) >= 2;
            EXPECT_EQ(bounceOf(ph) + 1, bounce);
            EXPECT_EQ(flagsOf(ph), PCL_PHOTON_CAUSTIC | PCL_PHOTON_AFTER_SPECULAR);
            EXPECT_NEAR(ph.y, 0.0f, 1e-5f);
            EXPECT_EQ(ph.rgbe, emittedRgbe);  // ρs = 1: the power is kept
        } else {
            EXPECT_EQ(t.counts[i], 0u);
        }
    }
    // The sphere subtends (1 - cos α)/2 of the sphere of directions, sin α = 0.5/2.
    double pHit = (1.0 - std::sqrt(1.0 - 0.0625)) / 2.0;
    EXPECT_GT(stored, size_t(0.5 * pHit * kPhotons));
    EXPECT_GT(refracted, stored / 2);  // most light goes through glass at these angles
}

// Bounce sampling on the device: a spot light shines down on a small quad of the material
// under test at y = 0 inside a large diffuse catcher sphere. Each bounce direction is recovered
// from the emitted ray (the hit on the quad) and the record on the catcher, then mapped through
// its analytic CDF onto an equal-probability 16 × 16 grid and chi-square tested (α = 0.01,
// Šidák over the two lobes); the dielectric's reflected share is tested against the mean
// Fresnel term and its refracted directions against Snell's law.
struct Bounce {
    Vec3 in, hit, out;  // incoming direction, point on the quad, outgoing direction
};

std::vector<Bounce> bouncesOffQuad(Material quad, uint32_t photons) {
    Scene s;
    s.materials.push_back(quad);
    int catcher = test::addMaterial(s, Vec3(0.5f));
    TriangleMesh q;
    q.material = 0;
    test::addQuad(q, Vec3(-0.3f, 0, -0.3f), Vec3(-0.3f, 0, 0.3f), Vec3(0.3f, 0, 0.3f), Vec3(0.3f, 0, -0.3f));
    s.meshes.push_back(q);
    Sphere c;
    c.radius = 100.0f;
    c.material = catcher;
    s.spheres.push_back(c);
    s.lights.push_back(test::spotLight(Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(1.0f), 0.93f, 0.92f));
    test::BuiltScene b = test::build(s);
    std::vector<uint32_t> first = lightFirstPhoton(b.buffers, photons, PCL_PASS_GLOBAL);
    PclPhotonParams p = makePhotonParams(b.geometry, b.buffers, PCL_PASS_GLOBAL, 17, 2, 0, first.back());
    auto rays = emitOnDevice(test::testDevice(), b.geometry, b.buffers, first, p);
    PhotonTraceResult t = tracePhotonsOnDevice(test::testDevice(), b.geometry, b.buffers, rays, p);
    std::vector<Bounce> out;
    const float eps = b.buffers.rayEpsilon;
    for (size_t i = 0; i < rays.size(); ++i) {
        Vec3 o(rays[i].ox, rays[i].oy, rays[i].oz), d(rays[i].dx, rays[i].dy, rays[i].dz);
        float th = -o.y / d.y;
        Vec3 hit = o + d * th;
        if (std::fabs(hit.x) > 0.29f || std::fabs(hit.z) > 0.29f) continue;  // missed the quad (or its edge)
        // The record on the catcher is the path's last one, made at bounce 1.
        if (t.counts[i] == 0) continue;
        const PclPhoton& r = t.slots[i * t.slotsPerPath + t.counts[i] - 1];
        if (((r.packed >> PCL_PHOTON_BOUNCE_SHIFT) & 0xFFu) != 1u) continue;
        Vec3 p2(r.x, r.y, r.z);
        Vec3 spawn = hit + Vec3(0, p2.y > 0 ? eps : -eps, 0);
        out.push_back({d, hit, normalize(p2 - spawn)});
    }
    return out;
}

double uniformGridPValue(const std::vector<std::pair<double, double>>& uv) {
    const int G = 16;
    std::vector<double> bins(G * G, 0.0);
    for (auto [u, v] : uv) {
        int iu = std::min(G - 1, std::max(0, int(u * G))), iv = std::min(G - 1, std::max(0, int(v * G)));
        bins[iu * G + iv] += 1;
    }
    double e = double(uv.size()) / (G * G), chi2 = 0;
    for (double c : bins) chi2 += (c - e) * (c - e) / e;
    double k = G * G - 1;
    double z = (std::cbrt(chi2 / k) - (1.0 - 2.0 / (9.0 * k))) / std::sqrt(2.0 / (9.0 * k));
    return 0.5 * std::erfc(z / std::sqrt(2.0));
}

double azimuth01(Vec3 w, Vec3 axis) {
    PclV3 t, b;
    sampling_basis(sampling_v3(axis.x, axis.y, axis.z), &t, &b);
    double phi = std::atan2(double(w.x * b.x + w.y * b.y + w.z * b.z), double(w.x * t.x + w.y * t.y + w.z * t.z));
    return (phi < 0 ? phi + 2 * 3.14159265358979323846 : phi) / (2 * 3.14159265358979323846);
}

const double kSidak2 = 1.0 - std::sqrt(1.0 - 0.01);

TEST(TracePhotons, DiffuseBounceIsCosineDistributed) {
    Material m;
    m.rhoD = Vec3(1.0f);  // P_d = 1: every photon bounces
    std::vector<Bounce> bs = bouncesOffQuad(m, 60000);
    ASSERT_GT(bs.size(), 30000u);
    std::vector<std::pair<double, double>> uv;
    const Vec3 n(0, 1, 0);
    for (const Bounce& b : bs) {
        ASSERT_GT(b.out.y, -1e-4f);
        double c = std::min(1.0, double(b.out.y));
        uv.push_back({1.0 - c * c, azimuth01(b.out, n)});  // sin²θ uniform under cosθ/π
    }
    double p = uniformGridPValue(uv);
    std::printf("diffuse bounce: %zu directions, chi-square p = %.4f\n", uv.size(), p);
    EXPECT_GT(p, kSidak2);
}

TEST(TracePhotons, GlossyBounceFollowsThePhongLobe) {
    Material m;
    m.rhoS = Vec3(1.0f);
    m.specular = SpecularKind::Glossy;
    m.phongExponent = 30.0f;
    std::vector<Bounce> bs = bouncesOffQuad(m, 60000);
    ASSERT_GT(bs.size(), 30000u);
    std::vector<std::pair<double, double>> uv;
    for (const Bounce& b : bs) {
        Vec3 r = b.in - Vec3(0, 2 * b.in.y, 0);  // mirror about y
        r = normalize(r);
        double c = std::min(1.0, double(dot(b.out, r)));
        uv.push_back({std::pow(c, 31.0), azimuth01(b.out, r)});  // cos^(n+1) α uniform
    }
    double p = uniformGridPValue(uv);
    std::printf("glossy bounce: %zu directions, chi-square p = %.4f\n", uv.size(), p);
    EXPECT_GT(p, kSidak2);
}

TEST(TracePhotons, DielectricSplitsByFresnelAndRefractsBySnell) {
    Material m;
    m.rhoS = Vec3(1.0f);
    m.specular = SpecularKind::Dielectric;
    m.ior = 1.5f;
    std::vector<Bounce> bs = bouncesOffQuad(m, 100000);
    ASSERT_GT(bs.size(), 50000u);
    double reflected = 0, expected = 0, variance = 0;
    for (const Bounce& b : bs) {
        double cosI = -b.in.y;
        double F = sampling_fresnel_dielectric(float(cosI), 1.0f / 1.5f);
        expected += F;
        variance += F * (1 - F);
        // Sines from the horizontal parts: √(1 - cos²) loses them near normal incidence.
        double sinI = std::sqrt(double(b.in.x) * b.in.x + double(b.in.z) * b.in.z);
        if (b.out.y > 0) {
            ++reflected;
            EXPECT_NEAR(b.out.y, cosI, 1e-4);  // mirror
        } else {
            double sinT = std::sqrt(double(b.out.x) * b.out.x + double(b.out.z) * b.out.z);
            EXPECT_NEAR(sinT, sinI / 1.5, 1e-4);  // Snell
            // In the plane of incidence: the horizontal parts point the same way.
            EXPECT_GT(b.out.x * b.in.x + b.out.z * b.in.z, -1e-6f);
        }
    }
    std::printf("dielectric: reflected %.0f of %zu, Fresnel expects %.1f ± %.1f\n", reflected, bs.size(), expected,
                std::sqrt(variance));
    EXPECT_NEAR(reflected, expected, 5.0 * std::sqrt(variance));
}

TEST(TracePhotons, RecordsOnSpheresLieOnTheirSurface) {
    Scene s;
    int white = test::addMaterial(s, Vec3(0.6f, 0.5f, 0.4f));
    s.meshes.push_back(test::closedBox(2.0f, white));
    for (int k = 0; k < 3; ++k) {
        Sphere sp;
        sp.centre = Vec3(-1.0f + k, -1.0f + 0.3f * k, 0.5f * k - 0.5f);
        sp.radius = 0.3f + 0.1f * k;
        sp.material = white;
        s.spheres.push_back(sp);
    }
    s.lights.push_back(test::pointLight(Vec3(0.5f, 1.5f, 0.0f), Vec3(1.0f)));
    test::BuiltScene b = test::build(s);
    PhotonMaps maps = globalOnly(b, 20000);
    size_t onSpheres = 0;
    for (const PclPhoton& p : maps.global) {
        Vec3 q(p.x, p.y, p.z);
        bool onBox = std::fabs(std::max(std::fabs(q.x), std::max(std::fabs(q.y), std::fabs(q.z))) - 2.0f) < 1e-5f;
        bool onSphere = false;
        for (const Sphere& sp : s.spheres)
            onSphere |= std::fabs(length(q - sp.centre) - sp.radius) < 1e-4f * sp.radius + 1e-6f;
        ASSERT_TRUE(onBox || onSphere) << q.x << " " << q.y << " " << q.z;
        onSpheres += onSphere;
    }
    EXPECT_GT(onSpheres, maps.global.size() / 50);
    // Coloured walls: the roulette keeps the expected power per channel, so records after a
    // bounce lean to red (ρ = 0.6, 0.5, 0.4) in power but not in count.
}

}  // namespace
}  // namespace pcl
