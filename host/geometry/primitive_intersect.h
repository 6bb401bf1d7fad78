// Ray–primitive tests of the host traversal, shared with the brute-force test so that a
// mismatch there can only come from the tree, never from two versions of the arithmetic.
// The device twins live in kernels/shared/bvh.h and use the same operation order, so the host
// and kernel agree to the last bit where the compilers do not contract a*b+c (bvh.h turns
// FP_CONTRACT off).
#pragma once
#include <cmath>
#include <cstdint>

#include "core/vec3.h"

namespace pcl {

// The closest-hit rule, used everywhere: the smaller t wins, a tie goes to the smaller primitive
// id, so the answer does not depend on the order the tree is walked in.
inline bool closerHit(float t, uint32_t prim, float bestT, uint32_t bestPrim) {
    return t < bestT || (t == bestT && prim < bestPrim);
}

// Möller–Trumbore (1997), two-sided. The triangle is v0 + u e1 + v e2; t is along the
// unnormalised direction d. A zero determinant (degenerate triangle or a ray in its plane)
// never hits. Returns false or true with t, u, v set.
inline bool intersectTriangle(Vec3 o, Vec3 d, Vec3 v0, Vec3 e1, Vec3 e2, float& t, float& u, float& v) {
    Vec3 p = cross(d, e2);
    float det = dot(e1, p);
    if (det == 0.0f) return false;
    float inv = 1.0f / det;
    Vec3 s = o - v0;
    float uu = dot(s, p) * inv;
    Vec3 q = cross(s, e1);
    float vv = dot(d, q) * inv;
    float tt = dot(e2, q) * inv;
    if (!(uu >= 0.0f && vv >= 0.0f && uu + vv <= 1.0f)) return false;
    t = tt;
    u = uu;
    v = vv;
    return true;
}

// Ray–sphere, numerically stable (Haines et al., "Precision Improvements for Ray/Sphere
// Intersection", Ray Tracing Gems ch. 7): the discriminant is formed from the squared distance
// of the centre to the ray's line, which does not cancel for small spheres far away, and the
// two roots come from q = -b - sign(b) sqrt(Δ) without subtracting nearly equal numbers.
// Writes both roots, t0 <= t1; returns false when the line misses.
inline bool intersectSphereRoots(Vec3 o, Vec3 d, Vec3 c, float r, float& t0, float& t1) {
    Vec3 f = o - c;
    float a = dot(d, d);
    float b = dot(f, d);                   // half the usual b
    Vec3 l = f - d * (b / a);              // offset of the centre from the line
    float disc = a * (r * r - dot(l, l));  // = b^2 - a c, without cancellation
    if (!(disc >= 0.0f)) return false;
    float cc = dot(f, f) - r * r;
    float q = -b - std::copysign(std::sqrt(disc), b);
    float ta = cc / q, tb = q / a;
    if (q == 0.0f) ta = tb;  // ray through the centre from the centre
    t0 = std::fmin(ta, tb);
    t1 = std::fmax(ta, tb);
    return true;
}

// The nearer root inside (tmin, tmax), or false.
inline bool intersectSphere(Vec3 o, Vec3 d, Vec3 c, float r, float tmin, float tmax, float& t) {
    float t0, t1;
    if (!intersectSphereRoots(o, d, c, r, t0, t1)) return false;
    if (t0 > tmin && t0 < tmax) {
        t = t0;
        return true;
    }
    if (t1 > tmin && t1 < tmax) {
        t = t1;
        return true;
    }
    return false;
}

}  // namespace pcl
