/* bvh.h: device traversal of the flat 8-wide BVH (layout in types.h), for the traversal,
 * photon-trace and camera kernels. One ray per work-item; the parallelism inside a work-item is
 * explicit: the eight child boxes of a node are slab-tested together with float8 (one vload8 per
 * SoA field) and a leaf's triangles four at a time with float4 Möller–Trumbore, because PoCL
 * does not vectorise a traversal loop across work-items but compiles vector types well
 * (README.md, "Benchmarks").
 *
 * The arithmetic is the host traversal's (host/geometry/bvh_traversal.cpp and
 * primitive_intersect.h) operation for operation, with FP_CONTRACT off so no a*b+c is fused:
 * on a device with IEEE division and sqrt (PoCL) the two agree to the last bit.
 *
 * Stack: the traversal pushes every child whose box is hit, nearest on top. The deepest a tree
 * can need is BvhStats::maxStack; the host passes it as -DPCL_BVH_STACK_SIZE
 * (DeviceGeometry::programOptions()), so the push-overflow guard never fires.
 *
 * Use: bvh_trace(nodes, packets, spheres, ray, anyHit, &hit) → hit.t, hit.u, hit.v (triangle
 * barycentrics: p = (1-u-v) p0 + u p1 + v p2), hit.prim (global id: triangles first, then
 * spheres; PCL_NO_HIT on a miss). */
#ifndef PCL_BVH_H
#define PCL_BVH_H

#include "types.h"

#ifdef __OPENCL_VERSION__

#ifndef PCL_BVH_STACK_SIZE
#define PCL_BVH_STACK_SIZE 64
#endif

/* Ize 2013, "Robust BVH Ray Traversal": the far distance scaled by 1 + 2γ(3). */
#define PCL_BVH_FAR_SCALE 1.0000004f

#pragma OPENCL FP_CONTRACT OFF

/* PoCL 3.1 (LLVM 15) left plain `inline` helpers as calls; forced inlining makes the any-hit
 * flag a compile-time constant in each entry point (no measurable speed change on PoCL). */
#ifdef __clang__
#define PCL_BVH_INLINE inline __attribute__((always_inline))
#else
#define PCL_BVH_INLINE inline
#endif

/* The ray o + t d, t in [tmin, tmax], at normalised shutter time `time`. */
inline PclRay bvh_ray(float ox, float oy, float oz, float dx, float dy, float dz, float tmin, float tmax,
                      float time) {
    PclRay r;
    r.ox = ox; r.oy = oy; r.oz = oz; r.tmin = tmin;
    r.dx = dx; r.dy = dy; r.dz = dz; r.tmax = tmax;
    r.time = time;
    r.pad0 = r.pad1 = r.pad2 = 0u;
    return r;
}

/* Prefetch a hit child while its siblings are sorted: on a 1M-triangle mesh under PoCL the
 * traversal waits on memory, and prefetching the pushed nodes and packets raised it from
 * 0.62x to 0.73x Embree (rays per CPU-second). Only where the target is a CPU that clang
 * compiles for; elsewhere (GPUs) it is left out. */
#if defined(__clang__) && (defined(__x86_64__) || defined(__i386__) || defined(__aarch64__))
#define PCL_BVH_PREFETCH(p) __builtin_prefetch(p)
#else
#define PCL_BVH_PREFETCH(p)
#endif

PCL_BVH_INLINE void bvh_prefetch_child(__global const PclBvhNode* nodes,
                                       __global const PclTriPacket* packets, uint child) {
    if (!(child & PCL_CHILD_LEAF)) {
        __global const char* p = (__global const char*)(nodes + child);
        PCL_BVH_PREFETCH(p); PCL_BVH_PREFETCH(p + 64); PCL_BVH_PREFETCH(p + 128); PCL_BVH_PREFETCH(p + 192);
    } else if (!(child & PCL_CHILD_SPHERES)) {
        __global const char* p = (__global const char*)(packets + (child & PCL_CHILD_INDEX_MASK));
        PCL_BVH_PREFETCH(p); PCL_BVH_PREFETCH(p + 64); PCL_BVH_PREFETCH(p + 128);
    }
}

/* A ray prepared for traversal: reciprocal direction and, per axis, the float offset of the
 * near-plane field in a PclBvhNode (lo or hi, by the direction's sign). */
typedef struct BvhRay {
    float ox, oy, oz, dx, dy, dz, ix, iy, iz, tmin, tmax, time;
    int nearX, nearY, nearZ, farX, farY, farZ;
} BvhRay;

/* Field offsets (in floats) inside PclBvhNode. */
#define PCL_BVH_LOX 0
#define PCL_BVH_HIX 24

PCL_BVH_INLINE BvhRay bvh_prepare(const PclRay r) {
    BvhRay b;
    b.ox = r.ox; b.oy = r.oy; b.oz = r.oz;
    b.dx = r.dx; b.dy = r.dy; b.dz = r.dz;
    /* 1/d clamped to ±FLT_MAX, as the host: no 0*inf = NaN in the slab test, so plain min/max. */
    b.ix = clamp(1.0f / r.dx, -FLT_MAX, FLT_MAX);
    b.iy = clamp(1.0f / r.dy, -FLT_MAX, FLT_MAX);
    b.iz = clamp(1.0f / r.dz, -FLT_MAX, FLT_MAX);
    b.tmin = r.tmin; b.tmax = r.tmax; b.time = r.time;
    b.nearX = (b.ix < 0.0f ? PCL_BVH_HIX : PCL_BVH_LOX);
    b.nearY = (b.iy < 0.0f ? PCL_BVH_HIX : PCL_BVH_LOX) + 8;
    b.nearZ = (b.iz < 0.0f ? PCL_BVH_HIX : PCL_BVH_LOX) + 16;
    b.farX = (b.ix < 0.0f ? PCL_BVH_LOX : PCL_BVH_HIX);
    b.farY = (b.iy < 0.0f ? PCL_BVH_LOX : PCL_BVH_HIX) + 8;
    b.farZ = (b.iz < 0.0f ? PCL_BVH_LOX : PCL_BVH_HIX) + 16;
    return b;
}

/* Slab test of all eight children: returns the entry distances in *tnear and a mask (-1 = hit).
 * Empty slots have inverted infinite boxes and always fail. */
PCL_BVH_INLINE int8 bvh_hit_children(__global const PclBvhNode* node, const BvhRay* r, float tfarLimit,
                             float8* tnear) {
    __global const float* f = (__global const float*)node;
    float8 t0x = (vload8(0, f + r->nearX) - r->ox) * r->ix;
    float8 t0y = (vload8(0, f + r->nearY) - r->oy) * r->iy;
    float8 t0z = (vload8(0, f + r->nearZ) - r->oz) * r->iz;
    float8 t1x = (vload8(0, f + r->farX) - r->ox) * r->ix;
    float8 t1y = (vload8(0, f + r->farY) - r->oy) * r->iy;
    float8 t1z = (vload8(0, f + r->farZ) - r->oz) * r->iz;
    float8 t0 = max(max(t0x, t0y), max(t0z, (float8)(r->tmin)));
    float8 t1 = min(min(t1x, t1y), min(t1z, (float8)(tfarLimit)));
    *tnear = t0;
    return t0 <= t1 * PCL_BVH_FAR_SCALE;
}

/* The closest-hit rule of the host: smaller t wins, a tie goes to the smaller primitive id. */
PCL_BVH_INLINE bool bvh_closer(float t, uint prim, float bestT, uint bestPrim) {
    return t < bestT || (t == bestT && prim < bestPrim);
}

/* Möller–Trumbore (1997) on the four lanes of a packet, two-sided; the host's
 * intersectTriangle lane by lane. Updates *best; returns true if a lane hit in (tmin, tmax)
 * (for any-hit, *best then holds that hit). */
PCL_BVH_INLINE bool bvh_hit_packet(__global const PclTriPacket* p, const BvhRay* r, bool anyHit,
                           PclHit* best) {
    /* Moving packets: shift the ray origin back by motion*time instead of moving the triangles. */
    float ox = r->ox - p->mx * r->time, oy = r->oy - p->my * r->time, oz = r->oz - p->mz * r->time;
    float4 e1x = vload4(0, p->e1x), e1y = vload4(0, p->e1y), e1z = vload4(0, p->e1z);
    float4 e2x = vload4(0, p->e2x), e2y = vload4(0, p->e2y), e2z = vload4(0, p->e2z);
    /* p = cross(d, e2) */
    float4 px = r->dy * e2z - r->dz * e2y;
    float4 py = r->dz * e2x - r->dx * e2z;
    float4 pz = r->dx * e2y - r->dy * e2x;
    float4 det = e1x * px + e1y * py + e1z * pz;
    float4 inv = 1.0f / det;
    float4 sx = ox - vload4(0, p->v0x), sy = oy - vload4(0, p->v0y), sz = oz - vload4(0, p->v0z);
    float4 u = (sx * px + sy * py + sz * pz) * inv;
    /* q = cross(s, e1) */
    float4 qx = sy * e1z - sz * e1y;
    float4 qy = sz * e1x - sx * e1z;
    float4 qz = sx * e1y - sy * e1x;
    float4 v = (r->dx * qx + r->dy * qy + r->dz * qz) * inv;
    float4 t = (e2x * qx + e2y * qy + e2z * qz) * inv;
    int4 ok = det != 0.0f && u >= 0.0f && v >= 0.0f && u + v <= 1.0f && t > r->tmin && t < r->tmax;
    if (!any(ok)) return false;
    float ts[4], us[4], vs[4];
    int oks[4];
    vstore4(t, 0, ts);
    vstore4(u, 0, us);
    vstore4(v, 0, vs);
    vstore4(ok, 0, oks);
    bool found = false;
    for (int l = 0; l < 4; ++l) {
        uint prim = p->prim[l];
        /* empty lanes have zero edges (det == 0), the prim check is belt and braces */
        if (!oks[l] || prim == PCL_NO_HIT) continue;
        if (anyHit || bvh_closer(ts[l], prim, best->t, best->prim)) {
            best->t = ts[l]; best->u = us[l]; best->v = vs[l]; best->prim = prim;
            found = true;
            if (anyHit) return true;
        }
    }
    return found;
}

/* Ray–sphere as the host's intersectSphereRoots (Haines et al., Ray Tracing Gems ch. 7). */
PCL_BVH_INLINE bool bvh_hit_sphere(__global const PclSphere* s, const BvhRay* r, bool anyHit,
                           PclHit* best) {
    float ox = r->ox - s->mx * r->time, oy = r->oy - s->my * r->time, oz = r->oz - s->mz * r->time;
    float fx = ox - s->cx, fy = oy - s->cy, fz = oz - s->cz;
    float a = r->dx * r->dx + r->dy * r->dy + r->dz * r->dz;
    float b = fx * r->dx + fy * r->dy + fz * r->dz;
    float ba = b / a;
    float lx = fx - r->dx * ba, ly = fy - r->dy * ba, lz = fz - r->dz * ba;
    float rr = s->radius * s->radius;
    float disc = a * (rr - (lx * lx + ly * ly + lz * lz));
    if (!(disc >= 0.0f)) return false;
    float cc = (fx * fx + fy * fy + fz * fz) - rr;
    float q = -b - copysign(sqrt(disc), b);
    float ta = cc / q, tb = q / a;
    if (q == 0.0f) ta = tb;
    float t0 = fmin(ta, tb), t1 = fmax(ta, tb);
    float t = (t0 > r->tmin && t0 < r->tmax) ? t0 : t1;
    if (!(t > r->tmin && t < r->tmax)) return false;
    if (!anyHit && !bvh_closer(t, s->prim, best->t, best->prim)) return false;
    best->t = t; best->u = 0.0f; best->v = 0.0f; best->prim = s->prim;
    return true;
}

/* All items of a leaf word; returns true if one hit (for any-hit: stop). */
PCL_BVH_INLINE bool bvh_hit_leaf(__global const PclTriPacket* packets, __global const PclSphere* spheres,
                         uint word, const BvhRay* r, bool anyHit, PclHit* hit) {
    uint first = word & PCL_CHILD_INDEX_MASK;
    uint count = ((word >> PCL_CHILD_COUNT_SHIFT) & PCL_CHILD_COUNT_MASK) + 1u;
    bool found = false;
    if (word & PCL_CHILD_SPHERES) {
        for (uint k = 0; k < count; ++k)
            if (bvh_hit_sphere(spheres + first + k, r, anyHit, hit)) {
                found = true;
                if (anyHit) return true;
            }
    } else {
        for (uint k = 0; k < count; ++k)
            if (bvh_hit_packet(packets + first + k, r, anyHit, hit)) {
                found = true;
                if (anyHit) return true;
            }
    }
    return found;
}

/* Closest hit (anyHit false) or any hit (true) of ray in (tmin, tmax). Returns whether it hit;
 * *hit gets t, u, v, prim (prim = PCL_NO_HIT and t = tmax on a miss). */
PCL_BVH_INLINE bool bvh_trace(__global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                      __global const PclSphere* spheres, const PclRay ray, bool anyHit,
                      PclHit* hit) {
    BvhRay r = bvh_prepare(ray);
    hit->t = ray.tmax; hit->u = 0.0f; hit->v = 0.0f; hit->prim = PCL_NO_HIT;
    uint stackWord[PCL_BVH_STACK_SIZE];
    float stackNear[PCL_BVH_STACK_SIZE];
    int sp = 1;
    stackWord[0] = 0u;
    stackNear[0] = r.tmin;
    while (sp > 0) {
        --sp;
        uint word = stackWord[sp];
        if (stackNear[sp] > hit->t * PCL_BVH_FAR_SCALE) continue;
        if (word & PCL_CHILD_LEAF) {
            if (bvh_hit_leaf(packets, spheres, word, &r, anyHit, hit) && anyHit) return true;
            continue;
        }
        __global const PclBvhNode* node = nodes + word;
        float8 tn8;
        int8 mask = bvh_hit_children(node, &r, hit->t, &tn8);
        if (!any(mask)) continue;
        float tn[8];
        int m[8];
        vstore8(tn8, 0, tn);
        vstore8(mask, 0, m);
        /* Insert the hit children far to near so the nearest ends on top of the stack. */
        int base = sp;
        for (int i = 0; i < PCL_BVH_WIDTH; ++i) {
            uint child = node->child[i];
            if (!m[i] || child == PCL_CHILD_EMPTY) continue;
            if (sp >= PCL_BVH_STACK_SIZE) continue;
            int j = sp++;
            while (j > base && stackNear[j - 1] < tn[i]) {
                stackNear[j] = stackNear[j - 1];
                stackWord[j] = stackWord[j - 1];
                --j;
            }
            stackNear[j] = tn[i];
            stackWord[j] = child;
            bvh_prefetch_child(nodes, packets, child);
        }
    }
    return hit->prim != PCL_NO_HIT;
}

#pragma OPENCL FP_CONTRACT ON

#endif /* __OPENCL_VERSION__ */
#endif /* PCL_BVH_H */
