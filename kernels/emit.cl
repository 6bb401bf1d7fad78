/* emit.cl: photons leaving the lights (kernels/README.md, "emit"), one photon per work-item.
 *
 * in:  params                  PclPhotonParams: pass seed, firstPhoton, batchSize, lightCount,
 *                              pass (PCL_PASS_GLOBAL / PCL_PASS_CAUSTIC), hasMotion, rayEpsilon
 *      lights[lightCount]      PclLight, powers exact (prep/scene_buffers)
 *      lightFirst[lightCount+1] photons of light l are [lightFirst[l], lightFirst[l+1]) of this
 *                              pass (largest-remainder allocation, prep/photon_allocation)
 *      projCells[]             marked projection-map cells, light l's at [projFirst, +projCount)
 *      env, envData[]          the sky (shared/environment.h), read by its light entry only
 *      primInfo, materials, materialTextures, texels, triangleUvs
 *                              a triangle light's material and its emission texture (read only
 *                              with PCL_TEXTURED, shared/texture.h)
 * out: rays[i], i < batchSize  PclPhotonRay of photon j = firstPhoton + i: origin, time, unit
 *                              direction, light index, flux Φ_l / n_l (caustic: Φ_l f_l / n_l)
 *
 * A triangle light with an emission texture: its Φ_l = π A L̄ holds only an estimate of the mean
 * radiance L̄ (prep/emission_texture.h), which allocated its photons; each photon carries
 * π A L(x) / n_l (caustic: × f_l) of the point x it leaves, L(x) = emission × texel there, so the
 * photons' flux sums to π ∫ L dA in expectation whatever the estimate.
 *
 * Random numbers: bounce 0 of (pass seed, j), stream PHOTON or CAUSTIC; u0 projection cell,
 * (u1, u2) position, u3 time, (u4, u5) direction.
 *
 * The sky (PCL_LIGHT_ENVIRONMENT): the direction toward the sky w by importance sampling its map
 * from (u4, u5), the photon travelling d = −w from a point of the disc of radius R (u1, u2)
 * perpendicular to d, 2R before the scene centre; its flux per channel is
 * π R² L_c(w) / (p(w) n) (caustic: × f), which sums to Φ = π R² ∫ L dω in expectation and exactly
 * for the luminance (p ∝ Y(L)). Caustic photons cross instead the disc of the ball around
 * every specular object (L.e1: centre, radius r; every ray that meets a specular surface crosses
 * it), 2R before its centre, with r in place of R: aimed without a projection map. */
#include "shared/types.h"
#include "shared/rng.h"
#include "shared/sampling.h"
#include "shared/environment.h"
#include "shared/texture.h"

#pragma OPENCL FP_CONTRACT OFF

/* The light owning photon j: the largest l with lightFirst[l] <= j (lights given no photons
 * have empty ranges and are skipped over). */
inline uint emit_light_of(__global const uint* lightFirst, uint lightCount, uint j) {
    uint lo = 0u, hi = lightCount;
    while (lo < hi) {
        uint mid = lo + (hi - lo + 1u) / 2u;
        if (lightFirst[mid] <= j)
            lo = mid;
        else
            hi = mid - 1u;
    }
    return lo;
}

__kernel void emit_photons(const PclPhotonParams params, __global const PclLight* lights,
                           __global const uint* lightFirst, __global const uint* projCells,
                           __global PclPhotonRay* rays, const PclEnvironment env,
                           __global const float* envData, __global const PclPrimInfo* primInfo,
                           __global const PclMaterial* materials,
                           __global const PclMaterialTextures* materialTextures, __global const float* texels,
                           __global const PclTriangleUv* triangleUvs) {
    const uint i = (uint)get_global_id(0);
    if (i >= params.batchSize) return;
    const uint j = params.firstPhoton + i;
    const bool caustic = params.pass == PCL_PASS_CAUSTIC;
    const ulong seed = (ulong)params.seedLo | ((ulong)params.seedHi << 32);
    const uint stream = caustic ? PCL_RNG_STREAM_CAUSTIC : PCL_RNG_STREAM_PHOTON;

    const uint l = emit_light_of(lightFirst, params.lightCount, j);
    const uint n = lightFirst[l + 1u] - lightFirst[l];
    const PclLight L = lights[l];

    uint w0[4], w1[4] = {0u, 0u, 0u, 0u};
    rng_block(seed, j, 0u, 0u, stream, w0);
    if (L.type != PCL_LIGHT_DIRECTIONAL) rng_block(seed, j, 0u, 1u, stream, w1);  /* (u4, u5) unused there */
    const float u0 = rng_u01(w0[0]), u1 = rng_u01(w0[1]), u2 = rng_u01(w0[2]), u3 = rng_u01(w0[3]);
    const float u4 = rng_u01(w1[0]), u5 = rng_u01(w1[1]);
    const float tau = params.hasMotion ? u3 : 0.0f;

    /* The pair this light samples its projection-map square with. */
    float s1 = L.type == PCL_LIGHT_DIRECTIONAL ? u1 : u4;
    float s2 = L.type == PCL_LIGHT_DIRECTIONAL ? u2 : u5;
    float flux = 1.0f;  /* f_l: the fraction of the square kept (1 in a global pass) */
    if (caustic && L.projCount > 0u) {
        uint c = (uint)floor(u0 * (float)L.projCount);
        c = min(c, L.projCount - 1u);
        const uint k = projCells[L.projFirst + c];
        const uint cx = k % PCL_PROJ_GRID, cy = k / PCL_PROJ_GRID;
        s1 = ((float)cx + s1) / (float)PCL_PROJ_GRID;
        s2 = ((float)cy + s2) / (float)PCL_PROJ_GRID;
        flux = (float)L.projCount / (float)(PCL_PROJ_GRID * PCL_PROJ_GRID);
    }

    const PclV3 axis = sampling_v3(L.axis[0], L.axis[1], L.axis[2]);
    PclV3 o = sampling_v3(L.p[0], L.p[1], L.p[2]);
    PclV3 d;
    float skyScale[3] = {0.0f, 0.0f, 0.0f}; /* the sky: π R² L_c(w) / p(w) */
    bool textured = false;                  /* a triangle light with an emission texture */
    float emitted[3] = {0.0f, 0.0f, 0.0f};  /* then π A L(x) */
    if (L.type == PCL_LIGHT_ENVIRONMENT) {
        PclV3 w;
        float Ls[3];
        const float pdf = env_sample(env, envData, s1, s2, &w, Ls);
        d = sampling_v3(-w.x, -w.y, -w.z);
        float x, y;
        sampling_concentric_disk(u1, u2, &x, &y);
        PclV3 t, b;
        sampling_basis(d, &t, &b);
        const float R = L.radius;
        const bool aimed = caustic && L.e1[3] > 0.0f;
        const float r = aimed ? L.e1[3] : R; /* the disc's radius */
        const float cx = aimed ? L.e1[0] : L.p[0], cy = aimed ? L.e1[1] : L.p[1], cz = aimed ? L.e1[2] : L.p[2];
        o.x = cx + r * (x * t.x + y * b.x) - 2.0f * R * d.x;
        o.y = cy + r * (x * t.y + y * b.y) - 2.0f * R * d.y;
        o.z = cz + r * (x * t.z + y * b.z) - 2.0f * R * d.z;
        for (int c = 0; c < 3; ++c) skyScale[c] = pdf > 0.0f ? PCL_PI_F * r * r * Ls[c] / pdf : 0.0f;
    } else if (L.type == PCL_LIGHT_POINT) {
        d = sampling_uniform_sphere(s1, s2);
    } else if (L.type == PCL_LIGHT_SPOT) {
        d = sampling_cone_direction(axis, sampling_spot_cos_theta(s1, L.cosInner, L.cosOuter),
                                    PCL_TWO_PI_F * s2);
    } else if (L.type == PCL_LIGHT_TRIANGLE) {
        float b0, b1;
        sampling_uniform_triangle(u1, u2, &b0, &b1);
        const float b2 = 1.0f - b0 - b1;
        const float eps = params.rayEpsilon;
        o.x = L.p[0] + b1 * L.e1[0] + b2 * L.e2[0] + L.motion[0] * tau + eps * L.axis[0];
        o.y = L.p[1] + b1 * L.e1[1] + b2 * L.e2[1] + L.motion[1] * tau + eps * L.axis[1];
        o.z = L.p[2] + b1 * L.e1[2] + b2 * L.e2[2] + L.motion[2] * tau + eps * L.axis[2];
        d = sampling_cosine_hemisphere(axis, s1, s2);
#ifdef PCL_TEXTURED
        const uint mat = primInfo[L.prim].material;
        if (materialTextures[mat].slot[PCL_TEXTURE_EMISSION].width != 0u) {
            textured = true;
            const PclMaterial M = materials[mat];
            float le[3];
            texture_emission_at(materialTextures, texels, triangleUvs, mat, L.prim, params.triangleCount, b1, b2,
                                M.emission, le);
            const float scale = PCL_PI_F * L.area;
            for (int c = 0; c < 3; ++c) emitted[c] = scale * le[c];
        }
#endif
    } else { /* directional: parallel rays from a disc of radius R, 2R behind the scene centre */
        float x, y;
        sampling_concentric_disk(s1, s2, &x, &y);
        PclV3 t, b;
        sampling_basis(axis, &t, &b);
        const float R = L.radius;
        o.x = L.p[0] + R * (x * t.x + y * b.x) - 2.0f * R * axis.x;
        o.y = L.p[1] + R * (x * t.y + y * b.y) - 2.0f * R * axis.y;
        o.z = L.p[2] + R * (x * t.z + y * b.z) - 2.0f * R * axis.z;
        d = axis;
    }

    PclPhotonRay r;
    r.ox = o.x;
    r.oy = o.y;
    r.oz = o.z;
    r.time = tau;
    r.dx = d.x;
    r.dy = d.y;
    r.dz = d.z;
    r.light = l;
    const float fn = (float)n;
    if (L.type == PCL_LIGHT_ENVIRONMENT) {
        for (int c = 0; c < 3; ++c) r.power[c] = skyScale[c] * (caustic ? flux : 1.0f) / fn;
    } else if (textured) {
        for (int c = 0; c < 3; ++c) r.power[c] = emitted[c] * (caustic ? flux : 1.0f) / fn;
    } else if (caustic) {
        r.power[0] = L.power[0] * flux / fn;
        r.power[1] = L.power[1] * flux / fn;
        r.power[2] = L.power[2] * flux / fn;
    } else {
        r.power[0] = L.power[0] / fn;
        r.power[1] = L.power[1] / fn;
        r.power[2] = L.power[2] / fn;
    }
    r.power[3] = 0.0f;
    rays[i] = r;
}
