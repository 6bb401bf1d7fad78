// BVH tests: the closest hit through the tree equals brute force over every primitive (same
// primitive id, t within 1e-5 relative) on 100 000 random rays per scene; any-hit agrees with
// closest-hit existence; degenerate inputs build and trace; the flat tree is well formed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <random>
#include <thread>

#include "../bench/bench_meshes.h"
#include "common/test_scenes.h"
#include "geometry/primitive_intersect.h"
#include "geometry/scene_geometry.h"
#if __has_include("scene/load_scene.h")
#include "scene/load_scene.h"
#define PCL_HAVE_LOAD_SCENE 1
#endif

namespace pcl {
namespace {

using test_scenes::randomSoup;
using test_scenes::shippedSceneFiles;

constexpr size_t kRays = 100000;
constexpr float kRelT = 1e-5f;

// Brute force over the Scene itself (not the flat arrays), with the same primitive tests.
PclHit bruteForce(const Scene& scene, const PclRay& r) {
    PclHit best{r.tmax, 0, 0, PCL_NO_HIT};
    Vec3 d{r.dx, r.dy, r.dz};
    uint32_t prim = 0;
    for (const auto& m : scene.meshes) {
        Vec3 o = Vec3(r.ox, r.oy, r.oz) - m.motion * r.time;
        for (size_t t = 0; t < m.triangleCount(); ++t, ++prim) {
            Vec3 p0 = m.positions[m.indices[3 * t]];
            Vec3 p1 = m.positions[m.indices[3 * t + 1]];
            Vec3 p2 = m.positions[m.indices[3 * t + 2]];
            float tt, u, v;
            if (intersectTriangle(o, d, p0, p1 - p0, p2 - p0, tt, u, v) && tt > r.tmin && tt < r.tmax &&
                closerHit(tt, prim, best.t, best.prim))
                best = {tt, u, v, prim};
        }
    }
    for (const auto& s : scene.spheres) {
        Vec3 o = Vec3(r.ox, r.oy, r.oz) - s.motion * r.time;
        float tt;
        if (intersectSphere(o, d, s.centre, s.radius, r.tmin, r.tmax, tt) && closerHit(tt, prim, best.t, best.prim))
            best = {tt, 0, 0, prim};
        ++prim;
    }
    return best;
}

// Rays from random points in (slightly beyond) the scene bounds in random directions, some
// aimed at a random primitive so that most rays hit something, some with a finite tmax.
std::vector<PclRay> randomRays(const Scene& scene, const Bounds3& bounds, size_t n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    // A box at least half as deep as it is wide, so flat scenes still get rays across them.
    Vec3 ext = vmax(bounds.extent(), Vec3(maxComponent(bounds.extent()) * 0.5f)) * 1.2f;
    Vec3 lo = bounds.centre() - ext * 0.5f;
    struct Target {
        Vec3 p;
        float jitter;
    };
    std::vector<Target> targets;
    for (const auto& m : scene.meshes)
        for (size_t i = 0; i < m.positions.size(); i += 1 + m.positions.size() / 4096)
            targets.push_back({m.positions[i], maxComponent(ext) * 0.02f});
    for (const auto& s : scene.spheres) targets.push_back({s.centre, s.radius * 2.0f});
    std::vector<PclRay> rays(n);
    for (auto& r : rays) {
        Vec3 o = lo + Vec3(u01(rng), u01(rng), u01(rng)) * ext;
        Vec3 d;
        if (!targets.empty() && u01(rng) < 0.5f) {
            const Target& t = targets[rng() % targets.size()];
            d = t.p + (Vec3(u01(rng), u01(rng), u01(rng)) - Vec3(0.5f)) * t.jitter - o;
        } else {
            float z = 2 * u01(rng) - 1, phi = 6.2831853f * u01(rng), s = std::sqrt(std::max(0.0f, 1 - z * z));
            d = Vec3(s * std::cos(phi), s * std::sin(phi), z) * (0.5f + 2 * u01(rng));  // unnormalised
        }
        r = PclRay{};
        r.ox = o.x;
        r.oy = o.y;
        r.oz = o.z;
        r.dx = d.x;
        r.dy = d.y;
        r.dz = d.z;
        r.tmin = u01(rng) < 0.5f ? 0.0f : 1e-4f;
        r.tmax = u01(rng) < 0.8f ? INFINITY : u01(rng) * 2.0f;
        r.time = u01(rng);
    }
    return rays;
}

struct Agreement {
    size_t rays = 0, hits = 0, primMismatch = 0, tMismatch = 0, anyMismatch = 0;
};

Agreement compareWithBruteForce(const Scene& scene, const SceneGeometry& g, size_t n, uint32_t seed) {
    auto rays = randomRays(scene, g.bounds(), n, seed);
    // Brute force is the slow side: split the rays over the hardware threads.
    unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    std::vector<Agreement> parts(threads);
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            Agreement& a = parts[t];
            for (size_t i = t * n / threads; i < (t + 1) * n / threads; ++i) {
                const PclRay& r = rays[i];
                PclHit h, b = bruteForce(scene, r);
                bool hit = g.intersect(r, h);
                a.rays++;
                a.hits += hit;
                if (h.prim != b.prim) {
                    if (a.primMismatch < 3)
                        std::printf("  mismatch: tree prim %u t %.9g, brute prim %u t %.9g\n", h.prim, h.t, b.prim,
                                    b.t);
                    a.primMismatch++;
                } else if (hit && std::fabs(h.t - b.t) > kRelT * std::fabs(b.t)) {
                    a.tMismatch++;
                }
                if (g.occluded(r) != hit) a.anyMismatch++;
            }
        });
    for (auto& th : pool) th.join();
    Agreement a;
    for (const auto& p : parts) {
        a.rays += p.rays;
        a.hits += p.hits;
        a.primMismatch += p.primMismatch;
        a.tMismatch += p.tMismatch;
        a.anyMismatch += p.anyMismatch;
    }
    std::printf("  %zu rays, %zu hits, prim mismatches %zu, t mismatches %zu, any-hit mismatches %zu\n", a.rays, a.hits,
                a.primMismatch, a.tMismatch, a.anyMismatch);
    return a;
}

// Every primitive referenced exactly once; every child box contains its subtree's primitives
// (over the whole shutter interval); leaf words in range.
void expectValidTree(const Scene& scene, const SceneGeometry& g) {
    std::vector<int> seen(g.primitiveCount(), 0);
    ASSERT_FALSE(g.nodes.empty());
    auto primBounds = [&](uint32_t prim) {
        Bounds3 b;
        PrimitiveRef ref = g.primitive(prim);
        if (ref.kind == PrimitiveRef::Sphere) {
            const Sphere& s = scene.spheres[ref.object];
            for (Vec3 c : {s.centre, s.centre + s.motion}) {
                b.extend(c - Vec3(s.radius));
                b.extend(c + Vec3(s.radius));
            }
        } else {
            const TriangleMesh& m = scene.meshes[ref.object];
            for (int k = 0; k < 3; ++k) {
                Vec3 p = m.positions[m.indices[3 * ref.index + k]];
                b.extend(p);
                b.extend(p + m.motion);
            }
        }
        return b;
    };
    auto contains = [](const Bounds3& outer, const Bounds3& inner) {
        return outer.lo.x <= inner.lo.x && outer.lo.y <= inner.lo.y && outer.lo.z <= inner.lo.z &&
               outer.hi.x >= inner.hi.x && outer.hi.y >= inner.hi.y && outer.hi.z >= inner.hi.z;
    };
    size_t boxErrors = 0, visited = 0;
    std::function<Bounds3(uint32_t)> walk = [&](uint32_t word) -> Bounds3 {
        Bounds3 sub;
        if (!(word & PCL_CHILD_LEAF)) {
            EXPECT_LT(word, g.nodes.size());
            const PclBvhNode& n = g.nodes[word];
            ++visited;
            for (int i = 0; i < PCL_BVH_WIDTH; ++i) {
                if (n.child[i] == PCL_CHILD_EMPTY) continue;
                Bounds3 c = walk(n.child[i]);
                Bounds3 box{{n.lox[i], n.loy[i], n.loz[i]}, {n.hix[i], n.hiy[i], n.hiz[i]}};
                if (!c.empty() && !contains(box, c)) ++boxErrors;
                sub.extend(c);
            }
            return sub;
        }
        uint32_t first = word & PCL_CHILD_INDEX_MASK;
        uint32_t count = ((word >> PCL_CHILD_COUNT_SHIFT) & PCL_CHILD_COUNT_MASK) + 1;
        if (word & PCL_CHILD_SPHERES) {
            EXPECT_LE(first + count, g.spheres.size());
            for (uint32_t k = 0; k < count; ++k) {
                uint32_t p = g.spheres[first + k].prim;
                EXPECT_GE(p, g.triangleCount());
                seen.at(p)++;
                sub.extend(primBounds(p));
            }
        } else {
            EXPECT_LE(first + count, g.packets.size());
            for (uint32_t k = 0; k < count; ++k)
                for (uint32_t p : g.packets[first + k].prim) {
                    if (p == PCL_NO_HIT) continue;
                    EXPECT_LT(p, g.triangleCount());
                    seen.at(p)++;
                    sub.extend(primBounds(p));
                }
        }
        return sub;
    };
    walk(0);
    EXPECT_EQ(visited, g.nodes.size()) << "unreachable nodes";
    EXPECT_EQ(boxErrors, 0u);
    for (size_t p = 0; p < seen.size(); ++p) ASSERT_EQ(seen[p], 1) << "primitive " << p;
}

// A closed, shared-vertex sphere mesh: rays hitting its edges and vertices exercise ties.
TriangleMesh tessellatedSphere(Vec3 c, float r, int rings, int segments) {
    TriangleMesh m;
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j < segments; ++j) {
            float th = 3.14159265f * i / rings, ph = 6.2831853f * j / segments;
            m.positions.push_back(c + Vec3(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)) * r);
        }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            uint32_t a = i * segments + j, b = i * segments + (j + 1) % segments;
            uint32_t c2 = a + segments, d = b + segments;
            if (i > 0) m.indices.insert(m.indices.end(), {a, b, c2});
            if (i < rings - 1) m.indices.insert(m.indices.end(), {b, d, c2});
        }
    return m;
}

Scene soupScene() {
    Scene s;
    s.meshes.push_back(randomSoup(1000, 1, 0.15f));
    s.meshes.push_back(tessellatedSphere({0.3f, -0.2f, 0.1f}, 0.5f, 16, 32));
    return s;
}

Scene sphereScene() {
    Scene s;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 500; ++i) {
        Sphere sp;
        sp.centre = Vec3(u(rng), u(rng), u(rng)) * 3.0f;
        sp.radius = 0.02f + 0.3f * std::fabs(u(rng));
        s.spheres.push_back(sp);
    }
    s.spheres.push_back({"tiny-far", Vec3(40.0f, 0, 0), 1e-3f, 0, Vec3(0.0f)});
    return s;
}

Scene movingScene() {
    Scene s;
    s.meshes.push_back(randomSoup(600, 2, 0.1f));
    s.meshes.push_back(randomSoup(400, 3, 0.1f, Vec3(0.4f, 0.0f, -0.2f)));
    s.meshes.push_back(randomSoup(400, 4, 0.1f, Vec3(0.0f, 0.7f, 0.0f)));
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 200; ++i) {
        Sphere sp;
        sp.centre = Vec3(u(rng), u(rng), u(rng));
        sp.radius = 0.05f + 0.05f * std::fabs(u(rng));
        sp.motion = i % 2 ? Vec3(u(rng), u(rng), u(rng)) * 0.5f : Vec3(0.0f);
        s.spheres.push_back(sp);
    }
    return s;
}

void expectAgreement(const Scene& scene, uint32_t seed, size_t rays = kRays) {
    SceneGeometry g = SceneGeometry::build(scene);
    expectValidTree(scene, g);
    const BvhStats& st = g.stats();
    std::printf(
        "  %u prims: %zu nodes, %zu packets, %zu leaves, depth %d (binary %d), stack %d, SAH %.2f, %.1f B/tri\n",
        g.primitiveCount(), st.nodes, st.packets, st.leaves, st.depth, st.binaryDepth, st.maxStack, st.sahCost,
        st.bytesPerTriangle());
    Agreement a = compareWithBruteForce(scene, g, rays, seed);
    EXPECT_EQ(a.primMismatch, 0u);
    EXPECT_EQ(a.tMismatch, 0u);
    EXPECT_EQ(a.anyMismatch, 0u);
    EXPECT_GT(a.hits, a.rays / 10) << "rays should mostly hit, or the test proves little";
}

TEST(Bvh, TriangleSoupMatchesBruteForce) { expectAgreement(soupScene(), 11); }
TEST(Bvh, SpheresMatchBruteForce) { expectAgreement(sphereScene(), 12); }
TEST(Bvh, MovingPrimitivesMatchBruteForce) { expectAgreement(movingScene(), 13); }

// The layout budget (≤ 80 bytes per triangle for nodes + packets) on a 100k-triangle
// scan-like mesh; packets must be mostly full for that (SAH counts whole packets).
TEST(Bvh, CompactLayout) {
    Scene s;
    s.meshes.push_back(displacedSphere(160, 320));
    SceneGeometry g = SceneGeometry::build(s);
    const BvhStats& st = g.stats();
    double fill = double(st.triangles) / (4.0 * double(st.packets));
    std::printf("  %zu triangles: %.1f bytes/triangle, packet fill %.3f, SAH %.2f, depth %d, stack %d\n", st.triangles,
                st.bytesPerTriangle(), fill, st.sahCost, st.depth, st.maxStack);
    EXPECT_LE(st.bytesPerTriangle(), 80.0);
    EXPECT_GE(fill, 0.85);
    EXPECT_LE(st.maxStack, 96);
    expectValidTree(s, g);
}

TEST(Bvh, EmptySceneNeverHits) {
    Scene s;
    SceneGeometry g = SceneGeometry::build(s);
    ASSERT_EQ(g.nodes.size(), 1u);
    PclRay r{};
    r.dx = 1.0f;
    r.tmax = INFINITY;
    PclHit h;
    EXPECT_FALSE(g.intersect(r, h));
    EXPECT_EQ(h.prim, PCL_NO_HIT);
    EXPECT_FALSE(g.occluded(r));
}

TEST(Bvh, SinglePrimitive) {
    Scene s;
    s.meshes.push_back(randomSoup(1, 9, 0.5f));
    expectAgreement(s, 14, 20000);
    Scene t;
    t.spheres.push_back(Sphere{});
    expectAgreement(t, 15, 20000);
}

TEST(Bvh, ManyIdenticalTrianglesStayShallow) {
    Scene s;
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    for (int i = 0; i < 20000; ++i) m.indices.insert(m.indices.end(), {0, 1, 2});
    s.meshes.push_back(m);
    SceneGeometry g = SceneGeometry::build(s);
    expectValidTree(s, g);
    EXPECT_LE(g.stats().binaryDepth, 16) << "median fallback should halve the count each level";
    // Every ray through the triangle hits it; the tie goes to the smallest id.
    PclRay r{};
    r.ox = 0.25f;
    r.oy = 0.25f;
    r.oz = 1.0f;
    r.dz = -1.0f;
    r.tmax = INFINITY;
    PclHit h;
    ASSERT_TRUE(g.intersect(r, h));
    EXPECT_EQ(h.prim, 0u);
    EXPECT_FLOAT_EQ(h.t, 1.0f);
    expectAgreement(s, 16, 2000);
}

TEST(Bvh, NanPrimitiveDoesNotCrash) {
    Scene s;
    s.meshes.push_back(randomSoup(100, 10, 0.2f));
    s.meshes[0].positions[5] = Vec3(NAN, 0.0f, 0.0f);
    SceneGeometry g = SceneGeometry::build(s);
    PclRay r{};
    r.oz = -5.0f;
    r.dz = 1.0f;
    r.tmax = INFINITY;
    PclHit h;
    g.intersect(r, h);  // any answer, no crash
    EXPECT_EQ(g.stats().triangles, 100u);
}

TEST(Bvh, PrimitiveIdsMapBackToTheScene) {
    Scene s;
    s.meshes.push_back(randomSoup(3, 1, 0.1f));
    s.meshes.push_back(TriangleMesh{});  // empty mesh in the middle
    s.meshes.push_back(randomSoup(2, 2, 0.1f));
    s.spheres.push_back(Sphere{});
    SceneGeometry g = SceneGeometry::build(s);
    EXPECT_EQ(g.primitive(2).object, 0u);
    EXPECT_EQ(g.primitive(3).object, 2u);
    EXPECT_EQ(g.primitive(4).index, 1u);
    EXPECT_EQ(g.primitive(5).kind, PrimitiveRef::Sphere);
    EXPECT_EQ(g.primitive(5).object, 0u);
}

#ifdef PCL_HAVE_LOAD_SCENE
TEST(Bvh, ShippedScenesMatchBruteForce) {
    std::vector<std::filesystem::path> files = shippedSceneFiles();
    ASSERT_FALSE(files.empty()) << "no shipped scenes found under scenes/";
    size_t scenes = 0;
    for (const auto& path : files) {
        Scene scene = loadScene(path.string());
        if (scene.triangleCount() > 200000) continue;  // brute force: the stress scene is for benchmarks
        std::printf("%s\n", path.filename().c_str());
        expectAgreement(scene, 17 + static_cast<uint32_t>(scenes));
        ++scenes;
    }
    std::printf("%zu shipped scenes checked\n", scenes);
}
#endif

}  // namespace
}  // namespace pcl
