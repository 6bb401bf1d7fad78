// Host traversal of the flat 8-wide BVH: the reference the traversal kernel is checked
// against, and what the CPU twin and the reference path tracer trace with. It walks exactly the
// arrays the kernel reads, with the same box test, stack discipline and primitive arithmetic.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <vector>

#include "geometry/primitive_intersect.h"
#include "geometry/scene_geometry.h"

namespace pcl {
namespace {

// Robust slab test (Ize 2013, "Robust BVH Ray Traversal"): scaling the far distance by
// 1 + 2γ(3) keeps a box whose true entry and exit coincide from being culled by rounding.
// It is applied after clamping to the best hit, so a box that holds a primitive at exactly
// the current best distance (a tie, decided by primitive id) is still entered.
constexpr float kFarScale = 1.0000004f;
// Stack entries on the C++ stack; a tree that needs more (BvhStats::maxStack, never seen in
// practice) gets a heap stack instead, so no ray is ever traced with a truncated stack.
constexpr int kStackSize = 128;

struct RayFrame {
    Vec3 o, d, inv;
    bool neg[3];  // direction sign per axis: which of lo/hi is the near plane
    float tmin, tmax, time;
};

// 1/d clamped to ±FLT_MAX: a zero direction component gives a huge finite reciprocal instead of
// an infinite one, so the slab test never forms 0·inf = NaN and plain min/max suffice (a libm
// fmin/fmax call per slab would cost more than the rest of the traversal).
inline float safeReciprocal(float d) { return std::clamp(1.0f / d, -FLT_MAX, FLT_MAX); }

RayFrame frameOf(const PclRay& r) {
    RayFrame f;
    f.o = {r.ox, r.oy, r.oz};
    f.d = {r.dx, r.dy, r.dz};
    f.inv = {safeReciprocal(r.dx), safeReciprocal(r.dy), safeReciprocal(r.dz)};
    f.neg[0] = f.inv.x < 0.0f;
    f.neg[1] = f.inv.y < 0.0f;
    f.neg[2] = f.inv.z < 0.0f;
    f.tmin = r.tmin;
    f.tmax = r.tmax;
    f.time = r.time;
    return f;
}

// Slab test of child i. Empty slots have inverted infinite boxes and always fail. The min/max
// order matches the kernel's (bvh_hit_children) so both cull the same boxes.
inline bool hitChild(const PclBvhNode& n, int i, const RayFrame& f, float tfarLimit, float& tnear) {
    float nx = f.neg[0] ? n.hix[i] : n.lox[i], fx = f.neg[0] ? n.lox[i] : n.hix[i];
    float ny = f.neg[1] ? n.hiy[i] : n.loy[i], fy = f.neg[1] ? n.loy[i] : n.hiy[i];
    float nz = f.neg[2] ? n.hiz[i] : n.loz[i], fz = f.neg[2] ? n.loz[i] : n.hiz[i];
    float t0 =
        std::max(std::max((nx - f.o.x) * f.inv.x, (ny - f.o.y) * f.inv.y), std::max((nz - f.o.z) * f.inv.z, f.tmin));
    float t1 =
        std::min(std::min((fx - f.o.x) * f.inv.x, (fy - f.o.y) * f.inv.y), std::min((fz - f.o.z) * f.inv.z, tfarLimit));
    tnear = t0;
    return t0 <= t1 * kFarScale;
}

// Start loading a pushed child while the rest is traversed: large scenes wait on memory
// (as in kernels/shared/bvh.h).
inline void prefetchChild(const SceneGeometry& g, uint32_t word) {
    const char* p = nullptr;
    if (!(word & PCL_CHILD_LEAF)) p = reinterpret_cast<const char*>(&g.nodes[word]);
    else if (!(word & PCL_CHILD_SPHERES)) p = reinterpret_cast<const char*>(&g.packets[word & PCL_CHILD_INDEX_MASK]);
    if (!p) return;
    for (int line = 0; line < 4; ++line) __builtin_prefetch(p + 64 * line);
}

// Visits the tree; `leaf` is called for each leaf word whose box is hit, nearest first, and
// returns true to stop. `limit` reads the current far limit (best hit so far).
template <class Limit, class Leaf>
void traverse(const SceneGeometry& g, const RayFrame& f, Limit limit, Leaf leaf) {
    uint32_t localWord[kStackSize];
    float localNear[kStackSize];
    std::vector<uint32_t> heapWord;
    std::vector<float> heapNear;
    uint32_t* stackWord = localWord;
    float* stackNear = localNear;
    const int capacity = std::max(kStackSize, g.stats().maxStack);
    if (capacity > kStackSize) {
        heapWord.resize(capacity);
        heapNear.resize(capacity);
        stackWord = heapWord.data();
        stackNear = heapNear.data();
    }
    int sp = 0;
    stackWord[sp] = 0;
    stackNear[sp] = f.tmin;
    ++sp;
    while (sp > 0) {
        --sp;
        uint32_t word = stackWord[sp];
        if (stackNear[sp] > limit() * kFarScale) continue;
        if (word & PCL_CHILD_LEAF) {
            if (leaf(word)) return;
            continue;
        }
        const PclBvhNode& n = g.nodes[word];
        // Children hit, sorted far to near so the nearest is pushed last and popped first.
        uint32_t hitWord[PCL_BVH_WIDTH];
        float hitNear[PCL_BVH_WIDTH];
        int count = 0;
        float far = limit();
        for (int i = 0; i < PCL_BVH_WIDTH; ++i) {
            float tn;
            if (n.child[i] == PCL_CHILD_EMPTY || !hitChild(n, i, f, far, tn)) continue;
            int j = count++;
            while (j > 0 && hitNear[j - 1] < tn) {
                hitNear[j] = hitNear[j - 1];
                hitWord[j] = hitWord[j - 1];
                --j;
            }
            hitNear[j] = tn;
            hitWord[j] = n.child[i];
        }
        for (int k = 0; k < count && sp < capacity; ++k) {
            stackWord[sp] = hitWord[k];
            stackNear[sp] = hitNear[k];
            ++sp;
            prefetchChild(g, hitWord[k]);
        }
    }
}

inline uint32_t leafCount(uint32_t word) { return ((word >> PCL_CHILD_COUNT_SHIFT) & PCL_CHILD_COUNT_MASK) + 1; }

// Calls hitFn(t, u, v, prim) for every hit in (tmin, tmax) in the leaf; hitFn returns true to
// stop early (any-hit).
template <class HitFn>
bool intersectLeaf(const SceneGeometry& g, uint32_t word, const RayFrame& f, HitFn hitFn) {
    const uint32_t first = word & PCL_CHILD_INDEX_MASK;
    const uint32_t count = leafCount(word);
    if (word & PCL_CHILD_SPHERES) {
        for (uint32_t k = 0; k < count; ++k) {
            const PclSphere& s = g.spheres[first + k];
            Vec3 o = f.o - Vec3(s.mx, s.my, s.mz) * f.time;
            float t0, t1;
            if (!intersectSphereRoots(o, f.d, {s.cx, s.cy, s.cz}, s.radius, t0, t1)) continue;
            float t = t0 > f.tmin && t0 < f.tmax ? t0 : t1;
            if (t > f.tmin && t < f.tmax && hitFn(t, 0.0f, 0.0f, s.prim)) return true;
        }
        return false;
    }
    for (uint32_t k = 0; k < count; ++k) {
        const PclTriPacket& p = g.packets[first + k];
        Vec3 o = f.o - Vec3(p.mx, p.my, p.mz) * f.time;
        for (int l = 0; l < 4; ++l) {
            if (p.prim[l] == PCL_NO_HIT) continue;
            float t, u, v;
            if (!intersectTriangle(o, f.d, {p.v0x[l], p.v0y[l], p.v0z[l]}, {p.e1x[l], p.e1y[l], p.e1z[l]},
                                   {p.e2x[l], p.e2y[l], p.e2z[l]}, t, u, v))
                continue;
            if (t > f.tmin && t < f.tmax && hitFn(t, u, v, p.prim[l])) return true;
        }
    }
    return false;
}

}  // namespace

bool SceneGeometry::intersect(const PclRay& ray, PclHit& hit) const {
    const RayFrame f = frameOf(ray);
    hit.t = ray.tmax;
    hit.u = hit.v = 0.0f;
    hit.prim = PCL_NO_HIT;
    traverse(
        *this, f, [&] { return hit.t; },
        [&](uint32_t word) {
            intersectLeaf(*this, word, f, [&](float t, float u, float v, uint32_t prim) {
                if (closerHit(t, prim, hit.t, hit.prim)) hit = {t, u, v, prim};
                return false;
            });
            return false;
        });
    return hit.prim != PCL_NO_HIT;
}

bool SceneGeometry::occluded(const PclRay& ray) const {
    const RayFrame f = frameOf(ray);
    bool found = false;
    traverse(
        *this, f, [&] { return f.tmax; },
        [&](uint32_t word) {
            found = intersectLeaf(*this, word, f, [](float, float, float, uint32_t) { return true; });
            return found;
        });
    return found;
}

}  // namespace pcl
