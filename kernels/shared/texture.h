/* texture.h: image texture lookup, in the common subset of C and OpenCL C, so the kernels and the
 * CPU twin sample the same texels the same way (kernels/README.md, "Textures"):
 *
 *   texture_transform_uv  KHR_texture_transform: (u', v') = T R S (u, v) as PclTexture.m holds it
 *   texture_wrap_texel    a texel index wrapped by repeat / clamp / mirror
 *   texture_bilinear      bilinear filtering of linear RGB texels, texel centres at (i + ½) / W
 *   texture_lookup        a material's texels at a triangle hit, one per textured slot
 *   texture_rho_d, texture_rho_s, texture_exponent, texture_metallic_roughness
 *                         one quantity (or glTF's coupled three) from those texels
 *   texture_material_at   the lookup and every mapping: the material at a hit
 *   texture_emission_at   the emitted radiance alone at a point of a triangle (light sampling)
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

/* ---- A material's texels at a hit ------------------------------------------------------- */

/* What a material's texture slots read at one point: value[slot] (linear RGB) where bit slot of
 * `has` is set. Filled by texture_lookup (the packed buffers) or by the reference's own lookup
 * (reference/surface.cpp), then mapped to the material's quantities by the functions below. */
typedef struct PclTexels {
    float value[PCL_TEXTURE_SLOTS][3];
    pcl_u32 has;
} PclTexels;

/* Every textured slot of material `material` at barycentrics (bu, bv) of primitive `prim`
 * (p = p0 + bu (p1 − p0) + bv (p2 − p0)), bilinearly filtered at the interpolated texture
 * coordinates of the slot's set. Nothing (has = 0) when the primitive is not a triangle
 * (spheres carry no texture coordinates; the loaders refuse textured spheres). */
PCL_INLINE void texture_lookup(PCL_GLOBAL const PclMaterialTextures* materialTextures, PCL_GLOBAL const float* texels,
                               PCL_GLOBAL const PclTriangleUv* triangleUvs, pcl_u32 material, pcl_u32 prim,
                               pcl_u32 triangleCount, float bu, float bv, PclTexels* out) {
    out->has = 0u;
    if (prim >= triangleCount) return;
    const float bw = 1.0f - bu - bv;
    for (int k = 0; k < PCL_TEXTURE_SLOTS; ++k) {
        const PclTexture t = materialTextures[material].slot[k];
        if (t.width == 0u) continue;
        PCL_GLOBAL const float* s = triangleUvs[prim].uv[t.texCoord & 1u];
        const float u = bw * s[0] + bu * s[2] + bv * s[4];
        const float v = bw * s[1] + bu * s[3] + bv * s[5];
        texture_bilinear(t, texels, u, v, out->value[k]);
        out->has |= 1u << k;
    }
}

/* ρd = the material's constant × its ρd texel (Phong mapping), in place. */
PCL_INLINE void texture_rho_d(const PclTexels* x, float rhoD[4]) {
    if ((x->has & (1u << PCL_TEXTURE_RHO_D)) == 0u) return;
    for (int c = 0; c < 3; ++c) rhoD[c] = rhoD[c] * x->value[PCL_TEXTURE_RHO_D][c];
}

/* ρs = the material's constant × its ρs texel (Phong mapping), in place. The loaders check
 * ρd + ρs ≤ 1 of the constants and texels lie in [0, 1], so every texel conserves energy. */
PCL_INLINE void texture_rho_s(const PclTexels* x, float rhoS[4]) {
    if ((x->has & (1u << PCL_TEXTURE_RHO_S)) == 0u) return;
    for (int c = 0; c < 3; ++c) rhoS[c] = rhoS[c] * x->value[PCL_TEXTURE_RHO_S][c];
}

/* The glossy exponent = lo + (hi − lo) × the texel's R (Phong mapping), in place. */
PCL_INLINE void texture_exponent(const PclMaterialTextures* t, const PclTexels* x, float* exponent) {
    if ((x->has & (1u << PCL_TEXTURE_EXPONENT)) == 0u) return;
    *exponent = t->exponentLo + (t->exponentHi - t->exponentLo) * x->value[PCL_TEXTURE_EXPONENT][0];
}

/* The Phong exponent of a glossy texel: the loaders' mapping of roughness r (scenes/README.md),
 * GGX α = r², n = 1/(2α²) − 1/2, at most 10⁴ (the material is glossy as a whole). */
#define PCL_TEXTURE_MAX_EXPONENT 1.0e4f
PCL_INLINE float texture_roughness_exponent(float roughness) {
    const float alpha = roughness * roughness;
    const float n = alpha > 0.0f ? 0.5f / (alpha * alpha) - 0.5f : PCL_TEXTURE_MAX_EXPONENT;
    return n < PCL_TEXTURE_MAX_EXPONENT ? n : PCL_TEXTURE_MAX_EXPONENT;
}

/* glTF metallic-roughness per texel (scenes/README.md, "Materials"): base = baseColorFactor ×
 * the base colour texel, metallic k = metallicFactor × B, roughness = roughnessFactor × G of
 * the metallic-roughness texel (1 for a slot without texture), then ρs = base k + (1 − k) F0,
 * ρd = base (1 − k)(1 − F0) and, for a glossy material, the exponent of the roughness; a texel
 * so rough that n < 1 reflects diffusely (ρd += ρs, ρs = 0), as the constant mapping does for a
 * whole material. ρd + ρs ≤ 1 holds by construction (and is rescaled as the loader does if
 * rounding says otherwise). A mirror material keeps its delta lobe; only ρd and ρs vary. */
PCL_INLINE void texture_metallic_roughness(const PclMaterialTextures* t, const PclTexels* x, PclMaterial* M) {
    float base[3], metallic = t->metallic, roughness = t->roughness;
    for (int c = 0; c < 3; ++c) base[c] = t->baseColor[c];
    if ((x->has & (1u << PCL_TEXTURE_RHO_D)) != 0u)
        for (int c = 0; c < 3; ++c) base[c] = base[c] * x->value[PCL_TEXTURE_RHO_D][c];
    if ((x->has & (1u << PCL_TEXTURE_EXPONENT)) != 0u) {
        metallic = metallic * x->value[PCL_TEXTURE_EXPONENT][2];
        roughness = roughness * x->value[PCL_TEXTURE_EXPONENT][1];
    }
    const float f0 = t->f0;
    for (int c = 0; c < 3; ++c) {
        M->rhoS[c] = base[c] * metallic + (1.0f - metallic) * f0;
        M->rhoD[c] = base[c] * ((1.0f - metallic) * (1.0f - f0));
    }
    if (M->specular == PCL_SPECULAR_GLOSSY) {
        const float n = texture_roughness_exponent(roughness);
        if (n < 1.0f) {
            for (int c = 0; c < 3; ++c) {
                M->rhoD[c] = M->rhoD[c] + M->rhoS[c];
                M->rhoS[c] = 0.0f;
            }
            M->exponent = 1.0f;
        } else {
            M->exponent = n;
        }
    }
    float sum = 0.0f;
    for (int c = 0; c < 3; ++c) sum = M->rhoD[c] + M->rhoS[c] > sum ? M->rhoD[c] + M->rhoS[c] : sum;
    if (sum > 1.0f)
        for (int c = 0; c < 3; ++c) {
            M->rhoD[c] = M->rhoD[c] / sum;
            M->rhoS[c] = M->rhoS[c] / sum;
        }
}

/* Emitted radiance = the material's constant × its emission texel (either mapping; glTF:
 * emissiveFactor × strength × emissiveTexture), in place. */
PCL_INLINE void texture_emission(const PclTexels* x, float emission[4]) {
    if ((x->has & (1u << PCL_TEXTURE_EMISSION)) == 0u) return;
    for (int c = 0; c < 3; ++c) emission[c] = emission[c] * x->value[PCL_TEXTURE_EMISSION][c];
}

/* The material M (its constants) at a point whose texels are x: every textured quantity. */
PCL_INLINE void texture_material(const PclMaterialTextures* t, const PclTexels* x, PclMaterial* M) {
    if (x->has == 0u) return;
    texture_emission(x, M->emission);
    if (t->mapping == PCL_TEXTURE_MAP_METALLIC_ROUGHNESS) {
        texture_metallic_roughness(t, x, M);
        return;
    }
    texture_rho_d(x, M->rhoD);
    texture_rho_s(x, M->rhoS);
    texture_exponent(t, x, &M->exponent);
}

/* The kernels' and the twin's entry: material `material` (M holds its constants) at
 * barycentrics (bu, bv) of primitive `prim`, in place. Untouched when the material has no
 * texture or the primitive is not a triangle. On the device only with PCL_TEXTURED defined
 * (the scene has textures). */
PCL_INLINE void texture_material_at(PCL_GLOBAL const PclMaterialTextures* materialTextures, PCL_GLOBAL const float* texels,
                                    PCL_GLOBAL const PclTriangleUv* triangleUvs, pcl_u32 material, pcl_u32 prim,
                                    pcl_u32 triangleCount, float bu, float bv, PclMaterial* M) {
#if PCL_DEVICE && !defined(PCL_TEXTURED)
    /* A program built for a scene without textures (DeviceScene::programOptions): every slot
     * has width 0, so nothing to read; compiled away, the kernels run as they did before. */
    return;
#endif
    PclTexels x;
    texture_lookup(materialTextures, texels, triangleUvs, material, prim, triangleCount, bu, bv, &x);
    if (x.has == 0u) return;
    const PclMaterialTextures t = materialTextures[material];
    texture_material(&t, &x, M);
}

/* The radiance triangle `prim` of material `material` emits at barycentrics (bu, bv), le[3]:
 * emission[] (the material's constant) × its emission texel there; emission[] alone without an
 * emission texture (or on the device without PCL_TEXTURED). Only the emission slot is read: the
 * light samplers (emit, next-event estimation) need nothing else of the material. */
PCL_INLINE void texture_emission_at(PCL_GLOBAL const PclMaterialTextures* materialTextures, PCL_GLOBAL const float* texels,
                                    PCL_GLOBAL const PclTriangleUv* triangleUvs, pcl_u32 material, pcl_u32 prim,
                                    pcl_u32 triangleCount, float bu, float bv, const float emission[4], float le[3]) {
    for (int c = 0; c < 3; ++c) le[c] = emission[c];
#if PCL_DEVICE && !defined(PCL_TEXTURED)
    return;
#endif
    const PclTexture t = materialTextures[material].slot[PCL_TEXTURE_EMISSION];
    if (t.width == 0u || prim >= triangleCount) return;
    PCL_GLOBAL const float* s = triangleUvs[prim].uv[t.texCoord & 1u];
    const float bw = 1.0f - bu - bv;
    const float u = bw * s[0] + bu * s[2] + bv * s[4];
    const float v = bw * s[1] + bu * s[3] + bv * s[5];
    float texel[3];
    texture_bilinear(t, texels, u, v, texel);
    for (int c = 0; c < 3; ++c) le[c] = le[c] * texel[c];
}

#endif /* PCL_TEXTURE_H */
