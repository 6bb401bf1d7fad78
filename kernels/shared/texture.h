/* texture.h: image texture lookup, in the common subset of C and OpenCL C, so the kernels and the
 * CPU twin sample the same texels the same way (kernels/README.md, "Textures"):
 *
 *   texture_transform_uv  KHR_texture_transform: (u', v') = T R S (u, v) as PclTexture.m holds it
 *   texture_wrap_texel    a texel index wrapped by repeat / clamp / mirror
 *   texture_bilinear      bilinear filtering of linear RGB texels, texel centres at (i + ½) / W
 *   texture_rho_d         a material's ρd at a triangle hit: the constant × its texture (if any)
 *
 * Coordinates: (0, 0) is the image's top-left corner, u runs right and v down (glTF's
 * convention); texel (i, j) covers [i, i+1)/W × [j, j+1)/H. Arithmetic is written left to right
 * and FP_CONTRACT is off on the device, so the host gets the same floats up to the rounding of
 * floor. */
#ifndef PCL_TEXTURE_H
#define PCL_TEXTURE_H

#include "compat.h"
#include "types.h"

#if PCL_DEVICE
  #pragma OPENCL FP_CONTRACT OFF
  #define PCL_TEX_FLOORF(x) floor(x)
  #define PCL_TEX_FINITE(x) isfinite(x)
#else
  #define PCL_TEX_FLOORF(x) floorf(x)
  #define PCL_TEX_FINITE(x) isfinite(x)
#endif

PCL_INLINE void texture_transform_uv(const PclTexture t, float u, float v, float* uOut, float* vOut) {
    *uOut = t.m[0] * u + t.m[1] * v + t.m[2];
    *vOut = t.m[3] * u + t.m[4] * v + t.m[5];
}

/* Texel index i (any integer within a few periods of [0, n)) under wrap mode `mode`. */
PCL_INLINE pcl_i32 texture_wrap_texel(pcl_i32 i, pcl_i32 n, pcl_u32 mode) {
    if (mode == PCL_WRAP_CLAMP) return i < 0 ? 0 : (i >= n ? n - 1 : i);
    if (mode == PCL_WRAP_MIRROR) {
        const pcl_i32 p = 2 * n;
        pcl_i32 k = i % p;
        k = k < 0 ? k + p : k;
        return k < n ? k : p - 1 - k;
    }
    {
        pcl_i32 k = i % n;
        return k < 0 ? k + n : k;
    }
}

/* The continuous coordinate u reduced to one period of its wrap mode before it is scaled to
 * texels, so the integer indices stay small whatever u is: [0, 1) repeat, [0, 2) mirror,
 * [-1, 2] clamp (beyond which clamping gives the edge texel anyway). */
PCL_INLINE float texture_reduce(float u, pcl_u32 mode) {
    if (!PCL_TEX_FINITE(u)) return 0.0f;
    if (mode == PCL_WRAP_CLAMP) return u < -1.0f ? -1.0f : (u > 2.0f ? 2.0f : u);
    if (mode == PCL_WRAP_MIRROR) return u - 2.0f * PCL_TEX_FLOORF(u * 0.5f);
    return u - PCL_TEX_FLOORF(u);
}

/* Bilinear filtering (texel centres at (i + ½)/W): out = the linear RGB at (u, v) after the
 * texture's transform and wrap. */
PCL_INLINE void texture_bilinear(const PclTexture t, PCL_GLOBAL const float* texels, float u, float v, float out[3]) {
    float tu, tv;
    texture_transform_uv(t, u, v, &tu, &tv);
    const pcl_u32 wrapU = t.wrap & 0xFFu, wrapV = (t.wrap >> 8) & 0xFFu;
    const pcl_i32 w = (pcl_i32)t.width, h = (pcl_i32)t.height;
    const float x = texture_reduce(tu, wrapU) * (float)w - 0.5f;
    const float y = texture_reduce(tv, wrapV) * (float)h - 0.5f;
    const float x0f = PCL_TEX_FLOORF(x), y0f = PCL_TEX_FLOORF(y);
    const float fx = x - x0f, fy = y - y0f;
    const pcl_i32 x0 = (pcl_i32)x0f, y0 = (pcl_i32)y0f;
    const pcl_i32 xa = texture_wrap_texel(x0, w, wrapU), xb = texture_wrap_texel(x0 + 1, w, wrapU);
    const pcl_i32 ya = texture_wrap_texel(y0, h, wrapV), yb = texture_wrap_texel(y0 + 1, h, wrapV);
    PCL_GLOBAL const float* rowA = texels + t.offset + (pcl_u64)ya * (pcl_u64)w * 3u;
    PCL_GLOBAL const float* rowB = texels + t.offset + (pcl_u64)yb * (pcl_u64)w * 3u;
    for (int c = 0; c < 3; ++c) {
        const float top = (1.0f - fx) * rowA[3 * xa + c] + fx * rowA[3 * xb + c];
        const float bottom = (1.0f - fx) * rowB[3 * xa + c] + fx * rowB[3 * xb + c];
        out[c] = (1.0f - fy) * top + fy * bottom;
    }
}

/* ρd of material `material` at barycentrics (bu, bv) of primitive `prim` (p = p0 + bu (p1 − p0)
 * + bv (p2 − p0)): rhoD (the material's constant, rgb) times its texture at the interpolated
 * texture coordinates, in place. Untouched when the material has no texture or the primitive
 * is not a triangle (spheres carry no texture coordinates; the loaders refuse textured spheres).
 * On the device only with PCL_TEXTURED defined (the scene has textures). */
PCL_INLINE void texture_rho_d(PCL_GLOBAL const PclTexture* materialTextures, PCL_GLOBAL const float* texels,
                              PCL_GLOBAL const PclTriangleUv* triangleUvs, pcl_u32 material, pcl_u32 prim,
                              pcl_u32 triangleCount, float bu, float bv, float rhoD[4]) {
#if PCL_DEVICE && !defined(PCL_TEXTURED)
    /* A program built for a scene without textures (DeviceScene::programOptions): every material
     * has width 0, so nothing to read; compiled away, the kernels run as they did before. */
    return;
#endif
    const PclTexture t = materialTextures[material];
    if (t.width == 0u || prim >= triangleCount) return;
    PCL_GLOBAL const float* s = triangleUvs[prim].uv[t.texCoord & 1u];
    const float bw = 1.0f - bu - bv;
    const float u = bw * s[0] + bu * s[2] + bv * s[4];
    const float v = bw * s[1] + bu * s[3] + bv * s[5];
    float texel[3];
    texture_bilinear(t, texels, u, v, texel);
    for (int c = 0; c < 3; ++c) rhoD[c] = rhoD[c] * texel[c];
}

#endif /* PCL_TEXTURE_H */
