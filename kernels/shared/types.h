/* types.h: the only definition of every buffer struct that crosses the host/device boundary.
 * Scalars only (a float3 is 16 bytes on the device and 12 on the host), padding spelled out,
 * and a size assert per struct on both sides. kernels/probe.cl reports the device-side sizes
 * so a test can compare them with sizeof on the host. */
#ifndef PCL_TYPES_H
#define PCL_TYPES_H

#include "compat.h"

/* ---- Rays and hits (traversal kernel I/O) ---------------------------------------------- */

typedef struct PclRay {
    pcl_f32 ox, oy, oz, tmin;
    pcl_f32 dx, dy, dz, tmax;
    pcl_f32 time;  /* normalised shutter time in [0,1]: moving primitives sit at p + motion*time */
    pcl_u32 pad0, pad1, pad2;
} PclRay;
PCL_STATIC_ASSERT(sizeof(PclRay) == 48, PclRay_size);

#define PCL_NO_HIT 0xFFFFFFFFu

typedef struct PclHit {
    pcl_f32 t, u, v;  /* distance along the (unnormalised) direction; barycentrics for triangles */
    pcl_u32 prim;     /* global primitive id (triangles first, then spheres) or PCL_NO_HIT */
} PclHit;
PCL_STATIC_ASSERT(sizeof(PclHit) == 16, PclHit_size);

/* ---- Wide BVH ----------------------------------------------------------------------------
 * Eight-way nodes whose child boxes are stored as structure-of-arrays, so a kernel loads each
 * coordinate with one vload8 and tests all eight boxes at once (PoCL does not vectorise a
 * traversal loop across work-items, but compiles explicit vector types well: DESIGN.md).
 * Node 0 is the root.
 *
 * Child word encoding:
 *   PCL_CHILD_EMPTY           unused slot
 *   bit 31 clear              interior node index
 *   bit 31 set                leaf; bit 30 set: sphere leaf, clear: triangle-packet leaf;
 *                             bits 26..29: item count - 1 (1..16 items);
 *                             bits 0..25: first item (PclTriPacket or PclSphere index). */
#define PCL_BVH_WIDTH 8
#define PCL_CHILD_EMPTY 0xFFFFFFFFu
#define PCL_CHILD_LEAF 0x80000000u
#define PCL_CHILD_SPHERES 0x40000000u
#define PCL_CHILD_COUNT_SHIFT 26
#define PCL_CHILD_COUNT_MASK 0xFu
#define PCL_CHILD_INDEX_MASK 0x03FFFFFFu

typedef struct PclBvhNode {
    pcl_f32 lox[8], loy[8], loz[8];
    pcl_f32 hix[8], hiy[8], hiz[8];
    pcl_u32 child[8];
} PclBvhNode;
PCL_STATIC_ASSERT(sizeof(PclBvhNode) == 224, PclBvhNode_size);

/* Four triangles tested together (Möller–Trumbore with float4). Empty lanes have prim ==
 * PCL_NO_HIT and degenerate edges. All lanes of a packet share one motion translation. */
typedef struct PclTriPacket {
    pcl_f32 v0x[4], v0y[4], v0z[4];
    pcl_f32 e1x[4], e1y[4], e1z[4];
    pcl_f32 e2x[4], e2y[4], e2z[4];
    pcl_u32 prim[4];
    pcl_f32 mx, my, mz;  /* translation over the shutter interval (0 for static geometry) */
    pcl_u32 pad0;
} PclTriPacket;
PCL_STATIC_ASSERT(sizeof(PclTriPacket) == 176, PclTriPacket_size);

typedef struct PclSphere {
    pcl_f32 cx, cy, cz, radius;
    pcl_f32 mx, my, mz;  /* translation over the shutter interval */
    pcl_u32 prim;        /* global primitive id */
} PclSphere;
PCL_STATIC_ASSERT(sizeof(PclSphere) == 32, PclSphere_size);

#endif /* PCL_TYPES_H */
