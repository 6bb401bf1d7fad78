/* trace_photons.cl: photon paths through the scene with Russian roulette, depositing a photon
 * record at every diffuse hit (kernels/README.md, "trace_photons"); one path per work-item.
 *
 * in:  params                  PclPhotonParams: pass seed, firstPhoton, batchSize, triangleCount,
 *                              maxDepth, storeGlobal, rayEpsilon
 *      rays[i], i < batchSize  PclPhotonRay from emit_photons
 *      nodes, packets, spheres the flat 8-wide BVH (shared/bvh.h)
 *      primInfo[prim]          normal or sphere centre/radius, material, motion
 *      materials[]             PclMaterial: ρd, ρs, specular kind, exponent, ior
 * out: slots[k*batchSize + i]  record k < S of path i, in hit order (S = maxDepth in both
 *                              passes: at most one record per hit); only k < counts[i] are
 *                              written. Slot-major, so the first records of neighbouring paths
 *                              share cache lines and pages: path-major (i*S + k) wrote one line
 *                              per path across a 100 MB buffer (TLB and write-allocate misses).
 *      counts[i]               records deposited by path i
 *      ends[i]                 b | cause << 8: the bounce the path ended at and PCL_END_*
 *
 * Random numbers: bounce b of (pass seed, j = firstPhoton + i), block 0: u0 roulette, u1
 * Fresnel choice, (u2, u3) direction.
 * options: -DPCL_BVH_STACK_SIZE=n (DeviceGeometry::programOptions) */
#include "shared/types.h"
#include "shared/rng.h"
#include "shared/sampling.h"
#include "shared/bvh.h"

#pragma OPENCL FP_CONTRACT OFF

inline PclPhoton trace_make_photon(PclV3 p, PclV3 nf, const float phi[3], PclV3 d, uint bounces, uint flags) {
    PclPhoton ph;
    ph.x = p.x;
    ph.y = p.y;
    ph.z = p.z;
    ph.rgbe = photon_rgbe_encode(phi[0], phi[1], phi[2]);
    ph.packed = photon_dir_encode(-d.x, -d.y, -d.z) | (bounces << PCL_PHOTON_BOUNCE_SHIFT) | flags;
    ph.normal = photon_normal_encode(nf.x, nf.y, nf.z);
    return ph;
}

inline void trace_path(const PclPhotonParams params, const bool caustic,
                       __global const PclPhotonRay* rays, __global const PclBvhNode* nodes,
                       __global const PclTriPacket* packets, __global const PclSphere* spheres,
                       __global const PclPrimInfo* primInfo, __global const PclMaterial* materials,
                       __global PclPhoton* slots, __global uint* counts, __global uint* ends) {
    const uint i = (uint)get_global_id(0);
    if (i >= params.batchSize) return;
    const uint j = params.firstPhoton + i;
    const ulong seed = (ulong)params.seedLo | ((ulong)params.seedHi << 32);
    const uint stream = caustic ? PCL_RNG_STREAM_CAUSTIC : PCL_RNG_STREAM_PHOTON;
    __global PclPhoton* slot = slots + i;  /* record k at slot[k * batchSize] */

    const PclPhotonRay start = rays[i];
    PclV3 o = sampling_v3(start.ox, start.oy, start.oz);
    PclV3 d = sampling_v3(start.dx, start.dy, start.dz);
    const float tau = start.time;
    float phi[3] = {start.power[0], start.power[1], start.power[2]};

    uint count = 0u, flags = 0u, cause = PCL_END_ESCAPED;
    uint b = 1u;
    for (;; ++b) {
        const PclRay ray = bvh_ray(o.x, o.y, o.z, d.x, d.y, d.z, 0.0f, INFINITY, tau);
        PclHit hit;
        if (!bvh_trace(nodes, packets, spheres, ray, false, &hit)) {
            cause = PCL_END_ESCAPED;
            break;
        }
        const PclV3 p = sampling_v3(o.x + hit.t * d.x, o.y + hit.t * d.y, o.z + hit.t * d.z);
        const PclPrimInfo info = primInfo[hit.prim];
        PclV3 n;
        if (hit.prim >= params.triangleCount) {
            const float cx = info.a + info.mx * tau, cy = info.b + info.my * tau,
                        cz = info.c + info.mz * tau;
            n = sampling_v3((p.x - cx) / info.radius, (p.y - cy) / info.radius, (p.z - cz) / info.radius);
        } else {
            n = sampling_v3(info.a, info.b, info.c);
        }
        const float dn = sampling_dot(d, n);
        const PclV3 nf = dn < 0.0f ? n : sampling_v3(-n.x, -n.y, -n.z);
        const PclMaterial M = materials[info.material];

        /* 1. Deposit at a surface with a diffuse part. The caustic path goes on to roulette
         * either way: a mixed surface may still bounce it specularly (Jensen's LS+D). */
        bool stored = false;
        if (sampling_max3(M.rhoD[0], M.rhoD[1], M.rhoD[2]) > 0.0f) {
            if (caustic)  /* LS+D: at least one specular bounce and no diffuse one */
                stored = (flags & PCL_PHOTON_AFTER_SPECULAR) != 0u && (flags & PCL_PHOTON_AFTER_DIFFUSE) == 0u;
            else
                stored = params.storeGlobal != 0u;
            if (stored)
                slot[(size_t)(count++) * params.batchSize] =
                    trace_make_photon(p, nf, phi, d, b - 1u, flags | (caustic ? PCL_PHOTON_CAUSTIC : 0u));
        }
        /* A caustic path that ends at this hit is STORED when it deposited here. */
        const uint endHere = (caustic && stored) ? PCL_END_STORED : PCL_END_ABSORBED;

        /* 2. Russian roulette with Jensen's per-channel probabilities (Jensen 2001, §5.3.2). */
        uint w[4];
        rng_block(seed, j, b, 0u, stream, w);
        const float z = rng_u01(w[0]), uF = rng_u01(w[1]), uA = rng_u01(w[2]), uB = rng_u01(w[3]);
        const float maxPhi = sampling_max3(phi[0], phi[1], phi[2]);
        float pd = 0.0f, ps = 0.0f;
        if (maxPhi > 0.0f) {
            pd = sampling_max3(M.rhoD[0] * phi[0], M.rhoD[1] * phi[1], M.rhoD[2] * phi[2]) / maxPhi;
            if (M.specular != PCL_SPECULAR_NONE)
                ps = sampling_max3(M.rhoS[0] * phi[0], M.rhoS[1] * phi[1], M.rhoS[2] * phi[2]) / maxPhi;
            const float sum = pd + ps;
            if (sum > 1.0f) {
                pd = pd / sum;
                ps = ps / sum;
            }
        }
        PclV3 dNew;
        if (z < pd) {
            if (caustic) { /* a diffuse bounce: no longer LS+D */
                cause = endHere;
                break;
            }
            dNew = sampling_cosine_hemisphere(nf, uA, uB);
            for (int c = 0; c < 3; ++c) phi[c] = phi[c] * M.rhoD[c] / pd;
            flags |= PCL_PHOTON_AFTER_DIFFUSE;
        } else if (z < pd + ps) {
            for (int c = 0; c < 3; ++c) phi[c] = phi[c] * M.rhoS[c] / ps;
            flags |= PCL_PHOTON_AFTER_SPECULAR;
            if (M.specular == PCL_SPECULAR_MIRROR) {
                dNew = sampling_reflect(d, nf);
            } else if (M.specular == PCL_SPECULAR_GLOSSY) {
                const float e = M.exponent;
                dNew = sampling_phong_lobe(sampling_reflect(d, nf), e, uA, uB);
                const float cosOut = sampling_dot(dNew, nf);
                if (!(cosOut > 0.0f)) {
                    cause = endHere;
                    break;
                }
                for (int c = 0; c < 3; ++c) phi[c] = phi[c] * (e + 2.0f) / (e + 1.0f) * cosOut;
            } else { /* dielectric: n is the outside normal */
                const bool entering = dn < 0.0f;
                const float eta = entering ? 1.0f / M.ior : M.ior;
                const float cosI = fabs(dn);
                const float F = sampling_fresnel_dielectric(cosI, eta);
                if (uF < F)
                    dNew = sampling_reflect(d, nf);
                else
                    dNew = sampling_refract(d, nf, cosI, eta);
            }
        } else {
            cause = endHere;
            break;
        }
        if (b >= params.maxDepth) {
            cause = PCL_END_MAX_DEPTH;
            break;
        }

        /* 3. Spawn off the side the new direction leaves by. */
        const float eps = params.rayEpsilon;
        const PclV3 ns = sampling_dot(dNew, nf) > 0.0f ? nf : sampling_v3(-nf.x, -nf.y, -nf.z);
        o = sampling_v3(p.x + ns.x * eps, p.y + ns.y * eps, p.z + ns.z * eps);
        d = dNew;
    }
    counts[i] = count;
    ends[i] = b | (cause << 8);
}

__kernel void trace_photons_global(const PclPhotonParams params, __global const PclPhotonRay* rays,
                                   __global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                                   __global const PclSphere* spheres, __global const PclPrimInfo* primInfo,
                                   __global const PclMaterial* materials, __global PclPhoton* slots,
                                   __global uint* counts, __global uint* ends) {
    trace_path(params, false, rays, nodes, packets, spheres, primInfo, materials, slots, counts, ends);
}

__kernel void trace_photons_caustic(const PclPhotonParams params, __global const PclPhotonRay* rays,
                                    __global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                                    __global const PclSphere* spheres, __global const PclPrimInfo* primInfo,
                                    __global const PclMaterial* materials, __global PclPhoton* slots,
                                   __global uint* counts, __global uint* ends) {
    trace_path(params, true, rays, nodes, packets, spheres, primInfo, materials, slots, counts, ends);
}
