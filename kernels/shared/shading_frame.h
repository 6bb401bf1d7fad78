/* shading_frame.h: the shading normal at a hit, in the common subset of C and OpenCL C, so the
 * kernels and the CPU twin shade with the same normal (kernels/README.md, "Shading normals" and
 * "Normal maps"):
 *
 *   shading_normal        the normal a triangle hit shades with, unit, on the side of the
 *                         geometric normal it is given: the interpolated vertex normal, perturbed
 *                         by the material's normal map (if any); the geometric normal itself for
 *                         spheres, triangles without normals or map, and programs built without
 *                         PCL_SHADING_NORMALS / PCL_NORMAL_MAPPED
 *   shading_perturb       a tangent-space normal-map texel turned into a world normal (glTF)
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
#include "texture.h"
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

PCL_INLINE PclV3 shading_cross(PclV3 a, PclV3 b) {
    return sampling_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

/* v / |v|, or v itself (0) when |v| is 0 or not finite. */
PCL_INLINE PclV3 shading_normalize(PclV3 v, int* ok) {
    const float len2 = sampling_dot(v, v);
    *ok = len2 > 0.0f && len2 < INFINITY;
    if (!*ok) return v;
    const float inv = 1.0f / PCL_SHADE_SQRTF(len2);
    return sampling_v3(v.x * inv, v.y * inv, v.z * inv);
}

/* glTF's tangent-space normal map (glTF 2.0 §3.9.3, material.normalTexture): the texel rgb (linear)
 * decoded as m = 2 rgb − 1, m.x and m.y times `scale`, and n' = normalise(m.x T + m.y B + m.z N)
 * with N the unit normal, T the tangent Gram–Schmidt orthonormalised against N and B = (N × T) w:
 * +x along ∂p/∂u, +y up the image (toward decreasing v: glTF's v runs down), +z along N. N where
 * the frame or the result degenerates. */
PCL_INLINE PclV3 shading_perturb(PclV3 n, PclV3 t, float w, const float rgb[3], float scale) {
    int ok;
    const float nt = sampling_dot(n, t);
    const PclV3 T = shading_normalize(sampling_v3(t.x - nt * n.x, t.y - nt * n.y, t.z - nt * n.z), &ok);
    if (!ok) return n;
    PclV3 B = shading_cross(n, T);
    B = sampling_v3(B.x * w, B.y * w, B.z * w);
    const float mx = (2.0f * rgb[0] - 1.0f) * scale, my = (2.0f * rgb[1] - 1.0f) * scale, mz = 2.0f * rgb[2] - 1.0f;
    const PclV3 p = shading_normalize(sampling_v3(mx * T.x + my * B.x + mz * n.x, mx * T.y + my * B.y + mz * n.y,
                                                  mx * T.z + my * B.z + mz * n.z),
                                      &ok);
    return ok ? p : n;
}

/* The shading normal of primitive `prim` (material `material`) at barycentrics (bu, bv)
 * (p = p0 + bu (p1 − p0) + bv (p2 − p0)), unit, on ng's side (ng: the unit geometric normal of
 * the hit, either orientation):
 *   1. N = (1 − bu − bv) n0 + bu n1 + bv n2 normalised from triangleNormals (when given and not
 *      all zero), else the geometric normal;
 *   2. with a normal map (normalMaps[material], width > 0): the tangent t and sign w interpolated
 *      likewise from triangleTangents (w's sign), the map sampled at the interpolated texture
 *      coordinates of its set (bilinear, its wrap and transform: shared/texture.h), and
 *      N ← shading_perturb(N, t, w, texel, scale), in the vertex normals' own orientation;
 *   3. flipped onto ng's side.
 * ng, bit for bit, where neither applies. Pointers may be null (the twin's empty buffers); on
 * the device step 1 is compiled only with PCL_SHADING_NORMALS and step 2 only with
 * PCL_NORMAL_MAPPED (DeviceScene::programOptions). */
PCL_INLINE PclV3 shading_normal(PCL_GLOBAL const PclTriangleNormals* triangleNormals,
                                PCL_GLOBAL const PclTriangleTangents* triangleTangents,
                                PCL_GLOBAL const PclNormalMap* normalMaps, PCL_GLOBAL const float* texels,
                                PCL_GLOBAL const PclTriangleUv* triangleUvs, pcl_u32 material, pcl_u32 prim,
                                pcl_u32 triangleCount, float bu, float bv, PclV3 ng) {
    if (prim >= triangleCount) return ng;
    const float bw = 1.0f - bu - bv;
    PclV3 n = ng;
    int changed = 0;
#if !PCL_DEVICE || defined(PCL_SHADING_NORMALS)
    if (triangleNormals) {
        PCL_GLOBAL const float* v = triangleNormals[prim].n;
        int ok;
        const PclV3 s = shading_normalize(sampling_v3(bw * v[0] + bu * v[3] + bv * v[6], bw * v[1] + bu * v[4] + bv * v[7],
                                                      bw * v[2] + bu * v[5] + bv * v[8]),
                                          &ok);
        if (ok) {
            n = s;
            changed = 1;
        }
    }
#endif
#if !PCL_DEVICE || defined(PCL_NORMAL_MAPPED)
    if (normalMaps && normalMaps[material].texture.width != 0u) {
        const PclNormalMap map = normalMaps[material];
        PCL_GLOBAL const float* tg = triangleTangents[prim].t;
        const PclV3 t = sampling_v3(bw * tg[0] + bu * tg[4] + bv * tg[8], bw * tg[1] + bu * tg[5] + bv * tg[9],
                                    bw * tg[2] + bu * tg[6] + bv * tg[10]);
        const float w = (bw * tg[3] + bu * tg[7] + bv * tg[11]) < 0.0f ? -1.0f : 1.0f;
        PCL_GLOBAL const float* s = triangleUvs[prim].uv[map.texture.texCoord & 1u];
        float rgb[3];
        texture_bilinear(map.texture, texels, bw * s[0] + bu * s[2] + bv * s[4], bw * s[1] + bu * s[3] + bv * s[5],
                         rgb);
        n = shading_perturb(n, t, w, rgb, map.scale);
        changed = 1;
    }
#endif
    if (!changed) return ng;
    return sampling_dot(n, ng) < 0.0f ? sampling_v3(-n.x, -n.y, -n.z) : n;
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
