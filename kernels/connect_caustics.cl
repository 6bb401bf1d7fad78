/* connect_caustics.cl: each caustic photon joined to the camera (kernels/README.md,
 * "connect_caustics"); one photon record per work-item.
 *
 * in:  params                  PclConnectParams: pass seed, photonCount, triangleCount,
 *                              rayEpsilon, findDistance
 *      camera                  PclCameraParams of the pass (frame, fields of view, thin lens, size)
 *      photons[i]              PclPhoton: the pass's caustic map (L S+ D records, trace_photons)
 *      times[i]                photon i's shutter time when params.hasTimes (scenes that move:
 *                              every ray of its connection is traced then); else unread
 *      nodes, packets, spheres the BVH; primInfo, materials; the texture and shading-normal
 *                              buffers (shared/texture.h, shared/shading_frame.h)
 * out: splats[i]               PclSplat: pixel and Φ ρd/π |ω_cam·n_g| (|ω_in·n_s| / |ω_in·n_g|) We G,
 *                              the light tracer's estimate of that pixel's average radiance
 *                              from photon i's path (host/reference/light_tracer.h); pixel
 *                              PCL_NO_SPLAT when the photon reaches none
 *
 * Only the diffuse part counts, as in the caustic map's estimate (ρd E / π) that this replaces
 * at the eye hits that see a surface directly (PclEyeEstimateParams::minDepth = 1): the sum
 * over a pass's photons estimates the same L S+ D E light, without the estimate's blur. The
 * record holds no primitive, so the surface is found again by a short ray along the record's
 * normal (on the side the photon came from). In scenes that move, the record's shutter time
 * comes beside it (the time emit gave its path), so the surface, its normal and the shadow ray
 * are those of that instant; the camera does not move.
 *
 * Random numbers: stream CONNECT, path = photon i, bounce 0, block 0: (u0, u1) the lens point. */
#include "shared/types.h"
#include "shared/rng.h"
#include "shared/sampling.h"
#include "shared/bvh.h"
#include "shared/camera.h"
#include "shared/eye.h"
#include "shared/texture.h"
#include "shared/shading_frame.h"

#pragma OPENCL FP_CONTRACT OFF

__kernel void connect_caustics(const PclConnectParams params, const PclCameraParams camera,
                               __global const PclPhoton* photons, __global const float* times,
                               __global const PclBvhNode* nodes,
                               __global const PclTriPacket* packets, __global const PclSphere* spheres,
                               __global const PclPrimInfo* primInfo, __global const PclMaterial* materials,
                               __global const PclMaterialTextures* materialTextures, __global const float* texels,
                               __global const PclTriangleUv* triangleUvs,
                               __global const PclTriangleNormals* triangleNormals,
                               __global const PclNormalMap* normalMaps,
                               __global const PclTriangleTangents* triangleTangents, __global PclSplat* splats) {
    const uint i = (uint)get_global_id(0);
    if (i >= params.photonCount) return;
    PclSplat out;
    out.pixel = PCL_NO_SPLAT;
    out.r = out.g = out.b = 0.0f;
    const PclPhoton ph = photons[i];
    const PclV3 p = sampling_v3(ph.x, ph.y, ph.z);
    const PclV3 nf = photon_normal_decode(ph.normal); /* geometric, on the photon's side */
    const float h = params.findDistance;
    const float tau = params.hasTimes ? times[i] : 0.0f;

    /* The record's surface: the nearest hit of p + n_f·h → p − n_f·h. */
    const PclRay find = bvh_ray(p.x + nf.x * h, p.y + nf.y * h, p.z + nf.z * h, -nf.x, -nf.y, -nf.z, 0.0f,
                                2.0f * h, tau);
    PclHit hit;
    if (!bvh_trace(nodes, packets, spheres, find, false, &hit)) {
        splats[i] = out;
        return;
    }
    const PclPrimInfo info = primInfo[hit.prim];
    PclV3 n;
    if (hit.prim >= params.triangleCount) {
        const PclV3 q = sampling_v3(find.ox - nf.x * hit.t, find.oy - nf.y * hit.t, find.oz - nf.z * hit.t);
        const float cx = info.a + info.mx * tau, cy = info.b + info.my * tau, cz = info.c + info.mz * tau;
        n = sampling_v3((q.x - cx) / info.radius, (q.y - cy) / info.radius, (q.z - cz) / info.radius);
    } else {
        n = sampling_v3(info.a, info.b, info.c);
    }
    const PclV3 ng = sampling_dot(n, nf) >= 0.0f ? n : sampling_v3(-n.x, -n.y, -n.z);
    const PclV3 nsh = shading_normal(triangleNormals, triangleTangents, normalMaps, texels, triangleUvs,
                                     info.material, hit.prim, params.triangleCount, hit.u, hit.v, n);
    const PclV3 ns = sampling_dot(n, nf) >= 0.0f ? nsh : sampling_v3(-nsh.x, -nsh.y, -nsh.z);
    PclMaterial M = materials[info.material];
    texture_material_at(materialTextures, texels, triangleUvs, info.material, hit.prim, params.triangleCount, hit.u,
                        hit.v, &M);

    /* The camera through a lens point. */
    const ulong seed = (ulong)params.seedLo | ((ulong)params.seedHi << 32);
    uint w[4];
    rng_block(seed, i, 0u, 0u, PCL_RNG_STREAM_CONNECT, w);
    uint pixel;
    PclV3 lens;
    float importance;
    if (!camera_connect(&camera, p, rng_u01(w[0]), rng_u01(w[1]), &pixel, &lens, &importance)) {
        splats[i] = out;
        return;
    }
    PclV3 toCam = sampling_v3(lens.x - p.x, lens.y - p.y, lens.z - p.z);
    const float dist = sqrt(sampling_dot(toCam, toCam));
    const PclV3 wc = sampling_v3(toCam.x / dist, toCam.y / dist, toCam.z / dist);
    const PclV3 wi = photon_dir_decode(ph.packed); /* toward where the photon came from */
    const float cosCamG = sampling_dot(wc, ng), cosCamS = sampling_dot(wc, ns);
    const float cosInG = sampling_dot(wi, ng), cosInS = sampling_dot(wi, ns);
    if (!(cosCamG > 0.0f) || !(cosCamS > 0.0f)) { /* the camera on the far side */
        splats[i] = out;
        return;
    }
    /* The adjoint BSDF's shading-normal factor |ω_in·n_s| |ω_cam·n_g| / (|ω_in·n_g| |ω_cam·n_s|)
     * times the cosine |ω_cam·n_s| of the BRDF's measure: 1 · cosCamG on flat surfaces. */
    float g = cosCamG;
    if (shading_is_smooth(nsh, n)) {
        if (!(cosInS > 0.0f) || !(cosInG > 0.0f)) {
            splats[i] = out;
            return;
        }
        g = cosInS * cosCamG / cosInG;
    }
    const float eps = params.rayEpsilon;
    const PclV3 o = eye_add_scaled(p, nf, eps);
    const PclRay shadow = bvh_ray(o.x, o.y, o.z, lens.x - o.x, lens.y - o.y, lens.z - o.z, 0.0f, 1.0f, tau);
    PclHit blocker;
    if (bvh_trace(nodes, packets, spheres, shadow, true, &blocker)) {
        splats[i] = out;
        return;
    }
    float phi[3];
    photon_rgbe_decode(ph.rgbe, &phi[0], &phi[1], &phi[2]);
    const float scale = g * importance / PCL_PI_F;
    out.r = phi[0] * M.rhoD[0] * scale;
    out.g = phi[1] * M.rhoD[1] * scale;
    out.b = phi[2] * M.rhoD[2] * scale;
    if (isfinite(out.r) && isfinite(out.g) && isfinite(out.b) && (out.r > 0.0f || out.g > 0.0f || out.b > 0.0f))
        out.pixel = pixel;
    else
        out.r = out.g = out.b = 0.0f;
    splats[i] = out;
}
