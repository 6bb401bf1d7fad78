/* shading_frame.h: the shading normal at a hit, in the common subset of C and OpenCL C, so the
 * kernels and the CPU twin shade with the same normal (kernels/README.md, "Shading normals"):
 *
 *   shading_normal        the interpolated vertex normal of a triangle hit, unit, on the side of
 *                         the geometric normal it is given; the geometric normal itself for
 *                         spheres, triangles without normals and programs built without
 *                         PCL_SHADING_NORMALS
 *   shading_is_smooth     whether a shading normal differs from the geometric one (the extra
 *                         side tests and the adjoint factor apply only then, so flat surfaces
 *                         take exactly the arithmetic they took before shading normals existed)
 *   shading_adjoint       pbrt-v4's factor for particles (photons) scattered with a shading normal
 *
 * The rule the kernels follow (as host/reference/bsdf.cpp does): the BSDF's frame and cosines use
 * the shading normal n_s; which side of the surface a direction is on, ray offsets, media sides
 * and the photon map's normal test use the geometric normal n_g. A direction on the wrong
 * geometric side gets nothing (no light through the surface, no light leak). */
#ifndef PCL_SHADING_FRAME_H
#define PCL_SHADING_FRAME_H

#include "compat.h"
#include "sampling.h"
#include "types.h"

/* No FP_CONTRACT pragma here (the including file's state holds): the kernels include this
 * header after the others, and a pragma in a header included earlier would change the contraction
 * of the headers after it (images no longer bit-identical to those before shading normals). */
#if PCL_DEVICE
  #define PCL_SHADE_SQRTF(x) sqrt(x)
  #define PCL_SHADE_FABSF(x) fabs(x)
#else
  #define PCL_SHADE_SQRTF(x) sqrtf(x)
  #define PCL_SHADE_FABSF(x) fabsf(x)
#endif

/* The shading normal of primitive `prim` at barycentrics (bu, bv) (p = p0 + bu (p1 − p0) +
 * bv (p2 − p0)): n = (1 − bu − bv) n0 + bu n1 + bv n2 normalised, flipped onto ng's side (ng is
 * the unit geometric normal of the hit, either orientation). ng itself where there is no shading
 * normal (a sphere, a triangle whose normals are zero, an interpolated normal of length 0). On the
 * device only with PCL_SHADING_NORMALS defined (DeviceScene::programOptions). */
PCL_INLINE PclV3 shading_normal(PCL_GLOBAL const PclTriangleNormals* triangleNormals, pcl_u32 prim,
                                pcl_u32 triangleCount, float bu, float bv, PclV3 ng) {
#if PCL_DEVICE && !defined(PCL_SHADING_NORMALS)
    /* A program built for a scene without shading normals: compiled away, the kernels run as
     * they did before shading normals existed. */
    return ng;
#endif
    if (prim >= triangleCount) return ng;
    PCL_GLOBAL const float* v = triangleNormals[prim].n;
    const float bw = 1.0f - bu - bv;
    const float x = bw * v[0] + bu * v[3] + bv * v[6];
    const float y = bw * v[1] + bu * v[4] + bv * v[7];
    const float z = bw * v[2] + bu * v[5] + bv * v[8];
    const float len2 = x * x + y * y + z * z;
    if (!(len2 > 0.0f) || !(len2 < INFINITY)) return ng;
    const float s = (x * ng.x + y * ng.y + z * ng.z) < 0.0f ? -1.0f : 1.0f;
    const float inv = s / PCL_SHADE_SQRTF(len2);
    return sampling_v3(x * inv, y * inv, z * inv);
}

PCL_INLINE int shading_is_smooth(PclV3 ns, PclV3 ng) { return ns.x != ng.x || ns.y != ng.y || ns.z != ng.z; }

/* |ω_in·n_s| |ω_out·n_g| / (|ω_in·n_g| |ω_out·n_s|): the adjoint BSDF's shading-normal factor
 * (Veach 1997 §5.3, pbrt-v4 §13.9) for a photon arriving from ω_in (toward the light) and
 * leaving along ω_out; 0 where the denominator is (a grazing direction). */
PCL_INLINE float shading_adjoint(PclV3 ns, PclV3 ng, PclV3 wIn, PclV3 wOut) {
    const float den = PCL_SHADE_FABSF(sampling_dot(wIn, ng)) * PCL_SHADE_FABSF(sampling_dot(wOut, ns));
    if (!(den > 0.0f)) return 0.0f;
    return PCL_SHADE_FABSF(sampling_dot(wIn, ns)) * PCL_SHADE_FABSF(sampling_dot(wOut, ng)) / den;
}

#endif /* PCL_SHADING_FRAME_H */
