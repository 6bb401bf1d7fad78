// Projection maps (host/prep/projection_map.h): conservative (no sample whose first hit is
// specular falls in an unmarked cell, checked by brute force through the light warps of
// kernels/README.md "emit") and reasonably tight.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <string>

#include "common/test_scenes.h"
#include "prep/projection_map.h"
#include "reference/sampling.h"
#include "scene/load_scene.h"

namespace pcl {
namespace {

constexpr int G = static_cast<int>(PCL_PROJ_GRID);
constexpr int kSamples = 200000;  // per light

std::string scenePath(const std::string& name) { return std::string(PHOTONCL_SOURCE_DIR) + "/scenes/" + name; }

// ---- The test's own warps, written from kernels/README.md "emit" with the reference host
// sampling functions (an independent witness of projection_map.cpp's warps).

// Spot: cosθ from s1 by inverting the smoothstep falloff's CDF; solved here by Newton's method
// on 2t³ − t⁴ = v (projection_map.cpp bisects).
double spotCosTheta(const PclLight& l, double s1) {
    double wIn = 1.0 - l.cosInner, wFall = 0.5 * (l.cosInner - l.cosOuter);
    double pIn = wIn / (wIn + wFall);
    if (s1 < pIn) return 1.0 - (s1 / pIn) * wIn;
    double v = (s1 - pIn) / (1.0 - pIn), t = 0.5;
    for (int i = 0; i < 100; ++i) {
        double f = 2 * t * t * t - t * t * t * t - v, df = 6 * t * t - 4 * t * t * t;
        if (df <= 0) break;
        t = std::clamp(t - f / df, 0.0, 1.0);
    }
    return l.cosOuter + t * (l.cosInner - l.cosOuter);
}

Vec3 v3(const float v[4]) { return Vec3(v[0], v[1], v[2]); }

void testRay(const PclLight& l, float s1, float s2, float u1, float u2, float time, Vec3& o, Vec3& d) {
    Vec3 t, b, n = v3(l.axis);
    makeBasis(n, t, b);
    switch (l.type) {
        case PCL_LIGHT_POINT:
            o = v3(l.p);
            d = sampleUniformSphere(s1, s2);
            break;
        case PCL_LIGHT_SPOT: {
            o = v3(l.p);
            float c = float(spotCosTheta(l, s1));
            d = fromLocal(t, b, n, std::sqrt(std::max(0.0f, 1.0f - c * c)), c, 2.0f * kPi * s2);
            break;
        }
        case PCL_LIGHT_TRIANGLE: {
            float b0, b1;
            sampleUniformTriangle(u1, u2, b0, b1);
            o = v3(l.p) + v3(l.e1) * b1 + v3(l.e2) * (1.0f - b0 - b1) + v3(l.motion) * time;
            d = sampleCosineHemisphere(n, s1, s2);
            break;
        }
        default: {
            float x, y;
            sampleConcentricDisk(s1, s2, x, y);
            o = v3(l.p) + (t * x + b * y) * l.radius - n * (2.0f * l.radius);
            d = n;
        }
    }
}

struct LightResult {
    uint32_t type = 0;
    size_t samples = 0, specularHits = 0, misses = 0;
    size_t marked = 0, hitCells = 0, ringCells = 0;  // ring: unhit cells next to a hit cell
};

struct Prepared {
    Scene scene;
    SceneGeometry geometry;
    SceneBuffers buffers;
};

Prepared prepare(Scene scene) {
    Prepared p{std::move(scene), {}, {}};
    p.geometry = SceneGeometry::build(p.scene);
    p.buffers = buildSceneBuffers(p.scene, p.geometry);
    buildProjectionMaps(p.scene, p.geometry, p.buffers);
    return p;
}

// Shoots `samples` samples, uniform over the light's sample square, through its warp and traces
// their first hit.
std::vector<LightResult> bruteForce(const Prepared& p, int samples, uint64_t seed) {
    std::vector<LightResult> out;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> U(0.0f, 1.0f);
    for (size_t li = 0; li < p.buffers.lights.size(); ++li) {
        const PclLight& l = p.buffers.lights[li];
        LightResult r;
        r.type = l.type;
        r.samples = samples;
        std::vector<char> marked(G * G, 0), hit(G * G, 0);
        for (uint32_t k = 0; k < l.projCount; ++k) marked.at(p.buffers.projCells.at(l.projFirst + k)) = 1;
        r.marked = l.projCount;
        std::uniform_int_distribution<int> cell(0, G * G - 1), edge(0, 7);
        const float below1 = std::nextafter(1.0f, 0.0f);
        for (int i = 0; i < samples; ++i) {
            // As the caustic pass samples a cell (kernels/README.md "emit"): s = (c + s')/G in
            // float, which may round onto the cell's far edge. One sample in four sits on a
            // cell edge (s' = 0 or the largest float below 1) in s1 or s2.
            int k = cell(rng), cx = k % G, cy = k / G;
            float a = U(rng), b = U(rng), u1 = U(rng), u2 = U(rng);
            switch (edge(rng)) {
                case 0: a = 0.0f; break;
                case 1: a = below1; break;
                case 2: b = 0.0f; break;
                case 3: b = below1; break;
                default: break;
            }
            float s1 = (float(cx) + a) / float(G), s2 = (float(cy) + b) / float(G);
            float time = p.buffers.hasMotion ? U(rng) : 0.0f;
            Vec3 o, d;
            testRay(l, s1, s2, u1, u2, time, o, d);
            PclRay ray{o.x, o.y, o.z, 0.0f, d.x, d.y, d.z, INFINITY, time, 0, 0, 0};
            PclHit h;
            bool any = p.geometry.intersect(ray, h);
            if (any && h.prim == l.prim) {  // grazing its own emitter: look past it
                ray.tmin = h.t * 1.0001f + 1e-7f;
                any = p.geometry.intersect(ray, h);
            }
            if (!any) continue;
            if (!isSpecular(p.buffers.materials[p.buffers.primInfo[h.prim].material])) continue;
            ++r.specularHits;
            hit[cy * G + cx] = 1;
            if (!marked[cy * G + cx]) ++r.misses;
        }
        for (int cy = 0; cy < G; ++cy)
            for (int cx = 0; cx < G; ++cx) {
                if (hit[cy * G + cx]) {
                    ++r.hitCells;
                    continue;
                }
                bool near = false;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        int x = cx + dx, y = cy + dy;
                        if (x >= 0 && y >= 0 && x < G && y < G && hit[y * G + x]) near = true;
                    }
                r.ringCells += near;
            }
        out.push_back(r);
    }
    return out;
}

const char* typeName(uint32_t t) {
    switch (t) {
        case PCL_LIGHT_POINT: return "point";
        case PCL_LIGHT_SPOT: return "spot";
        case PCL_LIGHT_TRIANGLE: return "triangle";
        default: return "directional";
    }
}

void report(const std::string& name, const std::vector<LightResult>& results) {
    for (size_t i = 0; i < results.size(); ++i) {
        const LightResult& r = results[i];
        std::printf("[projection] %-28s light %zu %-11s marked %4zu/%d (%.4f) | samples hitting specular %.4f "
                    "| cells hit %4zu (+ring %zu) | misses %zu\n",
                    name.c_str(), i, typeName(r.type), r.marked, G * G, double(r.marked) / (G * G),
                    double(r.specularHits) / r.samples, r.hitCells, r.ringCells, r.misses);
    }
}

// hitsExpected: every light must send some samples at a specular object (else the check is
// vacuous for it).
void expectConservative(const std::string& name, const Prepared& p, uint64_t seed, bool hitsExpected = false) {
    auto results = bruteForce(p, kSamples, seed);
    report(name, results);
    for (size_t i = 0; i < results.size(); ++i) {
        EXPECT_EQ(results[i].misses, 0u) << name << " light " << i << " (" << typeName(results[i].type)
                                         << "): specular first hits in unmarked cells";
        if (hitsExpected) {
            EXPECT_GT(results[i].specularHits, 100u) << name << " light " << i;
        }
    }
}

// ---- Scenes built in code -----------------------------------------------------------------

using test_scenes::addMaterial;  // Phong exponent 50
using test_scenes::addSphere;
using test_scenes::pointLight;

// Quads here are named "quad<mesh index>".
int addQuad(Scene& s, Vec3 corner, Vec3 u, Vec3 v, int material, Vec3 motion = Vec3(0.0f)) {
    return test_scenes::addQuad(s, corner, u, v, material, motion, "quad" + std::to_string(s.meshes.size()));
}

// A diffuse floor and back wall, a mirror sphere, a glass sphere and (optionally) a glossy quad;
// the mirror sphere moves when `motion`.
Scene specularRoom(bool glossyQuad, bool motion) {
    Scene s;
    s.path = "synthetic";
    int white = addMaterial(s, Vec3(0.7f));
    int mirror = addMaterial(s, Vec3(0.0f), Vec3(0.9f), SpecularKind::Mirror);
    int glass = addMaterial(s, Vec3(0.0f), Vec3(1.0f), SpecularKind::Dielectric);
    addQuad(s, Vec3(-2, 0, -2), Vec3(0, 0, 4), Vec3(4, 0, 0), white);
    addQuad(s, Vec3(-2, 0, 2), Vec3(0, 3, 0), Vec3(4, 0, 0), white);
    addSphere(s, Vec3(0.6f, 0.4f, 0.2f), 0.4f, mirror, motion ? Vec3(-0.5f, 0.2f, 0.0f) : Vec3(0.0f));
    addSphere(s, Vec3(-0.7f, 0.3f, -0.4f), 0.3f, glass);
    if (glossyQuad) {
        int glossy = addMaterial(s, Vec3(0.3f), Vec3(0.5f), SpecularKind::Glossy);
        addQuad(s, Vec3(-1.5f, 0.01f, 0.8f), Vec3(0.8f, 0, 0), Vec3(0, 0.6f, 0.5f), glossy);
    }
    s.camera.position = Vec3(0, 1, -4);
    s.camera.lookAt = Vec3(0, 0.5f, 0);
    if (motion) s.camera.shutterClose = 0.02f;
    return s;
}

Light spotLight(Vec3 p, Vec3 dir, float innerDeg, float outerDeg) {
    Light l;
    l.type = LightType::Spot;
    l.position = p;
    l.direction = normalize(dir);
    l.intensity = Vec3(2.0f);
    l.cosInner = std::cos(innerDeg * kPi / 180.0f);
    l.cosOuter = std::cos(outerDeg * kPi / 180.0f);
    return l;
}

void addAreaLight(Scene& s, Vec3 corner, Vec3 u, Vec3 v, Vec3 motion = Vec3(0.0f)) {
    int black = addMaterial(s, Vec3(0.0f), Vec3(0.0f), SpecularKind::None, Vec3(5.0f));
    Light l;
    l.type = LightType::Area;
    l.mesh = addQuad(s, corner, u, v, black, motion);
    s.lights.push_back(l);
}

Light directionalLight(Vec3 dir) {
    Light l;
    l.type = LightType::Directional;
    l.direction = normalize(dir);
    l.irradiance = Vec3(1.0f);
    return l;
}

// ---- Tests -----------------------------------------------------------------------------------

TEST(ProjectionMapWarp, MatchesTheReferenceWarpsAndTheSpotInversion) {
    Scene s = specularRoom(false, false);
    s.lights = {pointLight(Vec3(0, 2, 0)), spotLight(Vec3(0, 2, 0), Vec3(0.2f, -1, 0.1f), 15, 50),
                directionalLight(Vec3(0.3f, -1, 0.2f))};
    addAreaLight(s, Vec3(-0.3f, 2.5f, -0.3f), Vec3(0, 0, 0.6f), Vec3(0.6f, 0, 0));
    Prepared p = prepare(std::move(s));
    ASSERT_EQ(p.buffers.lights.size(), 5u);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> U(0.0f, 1.0f);
    for (const PclLight& l : p.buffers.lights) {
        for (int i = 0; i < 2000; ++i) {
            float s1 = U(rng), s2 = U(rng), u1 = U(rng), u2 = U(rng);
            Vec3 o, d;
            testRay(l, s1, s2, u1, u2, 0.0f, o, d);
            LightSampleRay w = warpLightSample(l, s1, s2, u1, u2, 0.0);
            ASSERT_LT(length(w.direction - d), 2e-5f) << typeName(l.type) << " s=(" << s1 << "," << s2 << ")";
            ASSERT_LT(length(w.origin - o), 2e-5f * (1.0f + length(o))) << typeName(l.type);
        }
    }
}

TEST(ProjectionMap, ShippedScenesAreConservative) {
    for (const char* name : {"cornell-box.json", "cornell-glossy.json", "cornell-spheres.json",
                             "cornell-spheres-point.json", "motion-dof.json"}) {
        Prepared p = prepare(loadScene(scenePath(name)));
        expectConservative(name, p, 11);
    }
}

#if PHOTONCL_HAVE_GLTF
TEST(ProjectionMap, ShippedGltfRoomIsConservative) {
    Prepared p = prepare(loadScene(scenePath("gltf-room.gltf")));
    expectConservative("gltf-room.gltf", p, 12);
}
#endif

TEST(ProjectionMap, SyntheticLightsAreConservative) {
    {
        Scene s = specularRoom(true, false);
        s.lights = {pointLight(Vec3(0.1f, 1.8f, 0.3f))};
        expectConservative("point", prepare(std::move(s)), 21, true);
    }
    {
        Scene s = specularRoom(true, true);
        s.lights = {pointLight(Vec3(-0.2f, 1.2f, -0.1f))};
        expectConservative("point, moving mirror", prepare(std::move(s)), 22, true);
    }
    {
        Scene s = specularRoom(true, false);
        s.lights = {spotLight(Vec3(0, 2, 0), Vec3(0.1f, -1, 0.05f), 20, 45),
                    spotLight(Vec3(1.5f, 1.0f, -1.0f), Vec3(-1, -0.3f, 0.5f), 60, 120)};  // wide: back half too
        expectConservative("spot", prepare(std::move(s)), 23, true);
    }
    {
        Scene s = specularRoom(true, true);
        s.lights.clear();
        addAreaLight(s, Vec3(-0.4f, 2.0f, -0.3f), Vec3(0.8f, 0, 0), Vec3(0, 0, 0.5f));  // facing down
        addAreaLight(s, Vec3(1.8f, 0.5f, -1.0f), Vec3(0, 0, 0.8f), Vec3(0, 0.6f, 0),
                     Vec3(0, 0.3f, 0));  // wall lamp facing -x, moving
        expectConservative("triangle", prepare(std::move(s)), 24, true);
    }
    {
        // A large bumpy mirror mesh (2 × 40² triangles: bounded by groups of triangles, not split).
        Scene s = specularRoom(false, false);
        int mirror = addMaterial(s, Vec3(0.0f), Vec3(0.8f), SpecularKind::Mirror);
        TriangleMesh m;
        const int n = 40;
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i)
                m.positions.push_back(Vec3(-1.5f + 1.2f * i / n, 0.3f + 0.05f * std::sin(0.9f * i) * std::cos(1.3f * j),
                                           -1.8f + 1.0f * j / n));
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
                m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
            }
        m.material = mirror;
        s.meshes.push_back(m);
        s.lights = {pointLight(Vec3(-0.5f, 1.5f, -1.0f)),
                    spotLight(Vec3(0.5f, 1.5f, -1.5f), Vec3(-0.5f, -1, 0.2f), 10, 40)};
        expectConservative("large mirror mesh", prepare(std::move(s)), 26, true);
    }
    {
        Scene s = specularRoom(true, true);
        s.lights = {directionalLight(Vec3(0.3f, -1, 0.2f)), directionalLight(Vec3(-1, -0.2f, 0.4f))};
        expectConservative("directional", prepare(std::move(s)), 25, true);
    }
}

TEST(ProjectionMap, LightInsideASpecularBallMarksEverything) {
    Scene s = specularRoom(false, false);
    s.lights = {pointLight(Vec3(0.6f, 0.4f, 0.5f))};  // inside the mirror ball's bounding sphere
    Prepared p = prepare(std::move(s));
    EXPECT_EQ(p.buffers.lights[0].projCount, PCL_PROJ_GRID * PCL_PROJ_GRID);
}

TEST(ProjectionMap, NoSpecularObjectsMeansEmptyMaps) {
    Prepared p = prepare(loadScene(scenePath("cornell-box.json")));
    ASSERT_FALSE(p.buffers.lights.empty());
    for (const PclLight& l : p.buffers.lights) EXPECT_EQ(l.projCount, 0u);
    EXPECT_TRUE(p.buffers.projCells.empty());

    Scene s = specularRoom(false, false);
    for (Material& m : s.materials) m.specular = SpecularKind::None, m.rhoS = Vec3(0.0f), m.rhoD = Vec3(0.5f);
    s.lights = {pointLight(Vec3(0, 2, 0)), directionalLight(Vec3(0, -1, 0))};
    Prepared q = prepare(std::move(s));
    for (const PclLight& l : q.buffers.lights) EXPECT_EQ(l.projCount, 0u);
}

TEST(ProjectionMap, CellsAreSortedAndInRange) {
    Prepared p = prepare(loadScene(scenePath("motion-dof.json")));
    for (const PclLight& l : p.buffers.lights) {
        ASSERT_LE(size_t(l.projFirst) + l.projCount, p.buffers.projCells.size());
        for (uint32_t k = 0; k < l.projCount; ++k) {
            uint32_t c = p.buffers.projCells[l.projFirst + k];
            EXPECT_LT(c, PCL_PROJ_GRID * PCL_PROJ_GRID);
            if (k) {
                EXPECT_LT(p.buffers.projCells[l.projFirst + k - 1], c);
            }
        }
        EXPECT_GT(l.projCount, 0u);  // chrome and gold spheres are in reach of both lights
    }
}

// Tight enough to be worth it: marked cells ≤ 4 × the cells some sample actually sends at a
// specular object, plus the ring of cells around those.
TEST(ProjectionMap, SpheresSceneMapsAreTight) {
    for (const char* name : {"cornell-spheres.json", "cornell-spheres-point.json"}) {
        Prepared p = prepare(loadScene(scenePath(name)));
        auto results = bruteForce(p, kSamples, 31);
        report(std::string(name) + " (tightness)", results);
        for (const LightResult& r : results) {
            EXPECT_EQ(r.misses, 0u);
            EXPECT_GT(r.hitCells, 0u);
            EXPECT_LE(r.marked, 4 * r.hitCells + r.ringCells) << name;
            EXPECT_LE(double(r.marked) / (G * G), 4.0 * double(r.specularHits) / r.samples + 0.05) << name;
        }
    }
}

}  // namespace
}  // namespace pcl
