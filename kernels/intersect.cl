/* intersect.cl: BVH traversal for a batch of rays, one ray per work-item.
 *
 * in:  rays[first + i]            PclRay: origin, tmin, direction (unnormalised), tmax, time
 *      nodes, packets, spheres    the flat 8-wide BVH of SceneGeometry (kernels/shared/types.h)
 *      first, count               the slice of rays this launch handles (launches are chunked)
 * out: hits[first + i]            PclHit: closest hit (t, u, v, prim), or prim = PCL_NO_HIT;
 *                                 intersect_any writes some hit in (tmin, tmax), not the closest
 * options: -DPCL_BVH_STACK_SIZE=n  at least BvhStats::maxStack of the tree */
#include "shared/bvh.h"

__kernel void intersect_closest(__global const PclRay* rays, __global const PclBvhNode* nodes,
                                __global const PclTriPacket* packets,
                                __global const PclSphere* spheres, __global PclHit* hits,
                                uint first, uint count) {
    uint i = get_global_id(0);
    if (i >= count) return;
    PclHit hit;
    bvh_trace(nodes, packets, spheres, rays[first + i], false, &hit);
    hits[first + i] = hit;
}

__kernel void intersect_any(__global const PclRay* rays, __global const PclBvhNode* nodes,
                            __global const PclTriPacket* packets, __global const PclSphere* spheres,
                            __global PclHit* hits, uint first, uint count) {
    uint i = get_global_id(0);
    if (i >= count) return;
    PclHit hit;
    bvh_trace(nodes, packets, spheres, rays[first + i], true, &hit);
    hits[first + i] = hit;
}
