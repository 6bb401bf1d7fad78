/* trace_photons.cl: photon paths through the scene with Russian roulette, depositing a photon
 * record at every diffuse hit (kernels/README.md, "trace_photons"); one path per work-item.
 *
 * in:  params                  PclPhotonParams: pass seed, firstPhoton, batchSize, triangleCount,
 *                              maxDepth, storeGlobal, rayEpsilon
 *      rays[i], i < batchSize  PclPhotonRay from emit_photons
 *      nodes, packets, spheres the flat 8-wide BVH (shared/bvh.h)
 *      primInfo[prim]          normal or sphere centre/radius, material, motion
 *      materials[]             PclMaterial: ρd, ρs, specular kind, exponent, ior, flags
 *      media[], primMedia[prim], lightMedia[light]
 *                              participating media (read only when params.hasMedia): the medium
 *                              table, the medium on either side of each primitive, the medium
 *                              each light emits into
 * out: slots[k*batchSize + i]  record k < S of path i, in hit order (S = maxDepth in both
 *                              passes: at most one record per hit); only k < counts[i] are
 *                              written. Slot-major, so the first records of neighbouring paths
 *                              share cache lines and pages: path-major (i*S + k) wrote one line
 *                              per path across a 100 MB buffer (TLB and write-allocate misses).
 *      counts[i]               records deposited by path i
 *      ends[i]                 b | cause << 8: the bounce the path ended at and PCL_END_*
 *      volumeSlots[k*batchSize + i], volumeCounts[i]
 *                              volume photons (PCL_PHOTON_VOLUME), laid out as slots/counts: at
 *                              most one per bounce, so S slots suffice; written only when
 *                              params.hasMedia (counts[i] = 0 otherwise)
 *
 * Media: in a medium every segment first samples a free flight (shared/medium.h); a scattering
 * event is a bounce of its own: a volume photon is stored there with the power scattered at the
 * event (Φ σs Tr/p: Σ ΔΦ over a volume estimates σs × fluence, what in-scattering needs), then
 * roulette with q = max_c ΔΦ[c] / max_c Φ[c] (the single-scattering albedo for a grey medium),
 * survivors carry ΔΦ/q in a Henyey–Greenstein direction. The global pass stores every event
 * (L(S|D|V)*V), the caustic pass only L S+ V (its path ends at the event, like at a diffuse bounce).
 * Invisible boundaries (PCL_MATERIAL_INTERFACE) change the medium and nothing else; refraction
 * changes it to the one beyond. Surface photons carry the transmittance weight Tr/P(t ≥ tMax).
 *
 * Random numbers: bounce b of (pass seed, j = firstPhoton + i), block 0: u0 roulette, u1
 * Fresnel choice, (u2, u3) direction. In a medium, block 1 + c for the c-th segment of bounce b
 * (c counts invisible boundaries crossed): u0 the channel, u1 the distance of the free flight; a
 * scattering event at bounce b takes block 0 (unused: no surface event at that bounce): u0
 * roulette, (u2, u3) HG direction.
 * options: -DPCL_BVH_STACK_SIZE=n (DeviceGeometry::programOptions) */
#include "shared/types.h"
#include "shared/rng.h"
#include "shared/sampling.h"
#include "shared/bvh.h"
#include "shared/medium.h"
#include "shared/texture.h"
#include "shared/shading_frame.h"
#include "shared/shutter_open.h"

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
                       __global PclPhoton* slots, __global uint* counts, __global uint* ends,
                       __global const PclMedium* media, __global const PclPrimMedium* primMedia,
                       __global const int* lightMedia, __global PclPhoton* volumeSlots,
                       __global uint* volumeCounts, __global const PclMaterialTextures* materialTextures,
                       __global const float* texels, __global const PclTriangleUv* triangleUvs,
                       __global const PclTriangleNormals* triangleNormals, __global const PclNormalMap* normalMaps,
                       __global const PclTriangleTangents* triangleTangents) {
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

    uint count = 0u, flags = 0u, cause = PCL_END_ABSORBED; /* every break sets it; kept when unreachable */
    uint volumeCount = 0u;
    int medium = params.hasMedia ? lightMedia[start.light] : PCL_NO_MEDIUM;
    uint segment = 0u; /* segments of bounce b so far (invisible boundaries crossed) */
    uint b = 1u;
    for (; medium != PCL_MEDIUM_UNREACHABLE; ++b) {
        const PclRay ray = bvh_ray(o.x, o.y, o.z, d.x, d.y, d.z, 0.0f, INFINITY, tau);
        PclHit hit;
        const bool found = bvh_trace(nodes, packets, spheres, ray, false, &hit);
        if (medium != PCL_NO_MEDIUM) {
            const PclMedium m = media[medium];
            uint v[4];
            rng_block(seed, j, b, 1u + segment, stream, v);
            float t, wt[3];
            const int scattered =
                medium_free_flight(m, found ? hit.t : INFINITY, rng_u01(v[0]), rng_u01(v[1]), phi, &t, wt);
            if (scattered) {
                const PclV3 x = sampling_v3(o.x + t * d.x, o.y + t * d.y, o.z + t * d.z);
                for (int c = 0; c < 3; ++c) wt[c] = phi[c] * wt[c]; /* ΔΦ: the power scattered here */
                const bool store = caustic ? ((flags & PCL_PHOTON_AFTER_SPECULAR) != 0u &&
                                              (flags & PCL_PHOTON_AFTER_DIFFUSE) == 0u)
                                           : params.storeGlobal != 0u;
                if (store) {
                    PclPhoton ph = trace_make_photon(x, sampling_v3(0.0f, 0.0f, 0.0f), wt, d, b - 1u,
                                                     flags | PCL_PHOTON_VOLUME | (caustic ? PCL_PHOTON_CAUSTIC : 0u));
                    ph.normal = 0u;
                    volumeSlots[(size_t)(volumeCount++) * params.batchSize + i] = ph;
                }
                if (caustic) { /* L S+ V ends here; any other caustic path is no longer L S+ */
                    cause = store ? PCL_END_STORED : PCL_END_ABSORBED;
                    break;
                }
                const float maxPhi = sampling_max3(phi[0], phi[1], phi[2]);
                float q = maxPhi > 0.0f ? sampling_max3(wt[0], wt[1], wt[2]) / maxPhi : 0.0f;
                q = q > 1.0f ? 1.0f : q;
                rng_block(seed, j, b, 0u, stream, v);
                if (!(rng_u01(v[0]) < q)) {
                    cause = PCL_END_ABSORBED;
                    break;
                }
                for (int c = 0; c < 3; ++c) phi[c] = wt[c] / q;
                flags |= PCL_PHOTON_AFTER_DIFFUSE;
                if (b >= params.maxDepth) {
                    cause = PCL_END_MAX_DEPTH;
                    break;
                }
                const float mu = medium_hg_cos(m.g, rng_u01(v[2]));
                d = sampling_cone_direction(d, mu, PCL_TWO_PI_F * rng_u01(v[3]));
                o = x;
                segment = 0u;
                continue;
            }
            for (int c = 0; c < 3; ++c) phi[c] = phi[c] * wt[c];
            if (!(sampling_max3(phi[0], phi[1], phi[2]) > 0.0f)) { /* to infinity, or no power left */
                cause = found ? PCL_END_ABSORBED : PCL_END_ESCAPED;
                break;
            }
        }
        if (!found) {
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
        /* The shading normal (on n's side) and its twin sf on the photon's side: the scattering
         * frame; a smooth one adds the adjoint factor and the geometric side tests below. */
        const PclV3 nsh = shading_normal(triangleNormals, triangleTangents, normalMaps, texels, triangleUvs,
                                         info.material, hit.prim, params.triangleCount, hit.u, hit.v, n);
        const PclV3 sf = dn < 0.0f ? nsh : sampling_v3(-nsh.x, -nsh.y, -nsh.z);
        const bool smooth = shading_is_smooth(nsh, n);
        PclMaterial M = materials[info.material];
        /* The material at the hit: its constants times its textures (shared/texture.h). */
        texture_material_at(materialTextures, texels, triangleUvs, info.material, hit.prim, params.triangleCount,
                            hit.u, hit.v, &M);
        if (params.hasMedia) {
            if ((M.flags & PCL_MATERIAL_INTERFACE) != 0u) {
                /* An invisible boundary: straight on in the medium beyond, same bounce. The
                 * segment count bounds the crossings (a ray meets finitely many surfaces). */
                medium = dn < 0.0f ? primMedia[hit.prim].inside : primMedia[hit.prim].outside;
                const float eps = params.rayEpsilon;
                o = sampling_v3(p.x - nf.x * eps, p.y - nf.y * eps, p.z - nf.z * eps);
                if (++segment >= PCL_MAX_SEGMENTS) {
                    cause = PCL_END_MAX_DEPTH;
                    break;
                }
                --b; /* the loop's ++b: the crossing is not a bounce */
                continue;
            }
            segment = 0u;
        }

        /* 1. Deposit at a surface with a diffuse part. The caustic path goes on to roulette
         * either way: a mixed surface may still bounce it specularly (Jensen's LS+D). */
        bool stored = false;
        if (sampling_max3(M.rhoD[0], M.rhoD[1], M.rhoD[2]) > 0.0f) {
            if (caustic)  /* LS+D: at least one specular bounce and no diffuse one */
                stored = (flags & PCL_PHOTON_AFTER_SPECULAR) != 0u && (flags & PCL_PHOTON_AFTER_DIFFUSE) == 0u;
            else
                stored = params.storeGlobal != 0u;
            /* The global map keeps a moving surface's photons where it sits at shutter open. */
            if (stored)
                slot[(size_t)(count++) * params.batchSize] =
                    trace_make_photon(caustic ? p : shutter_open_position(info, p, tau), nf, phi, d,
                                      b - 1u, flags | (caustic ? PCL_PHOTON_CAUSTIC : 0u));
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
        bool refracted = false;
        if (z < pd) {
            if (caustic) { /* a diffuse bounce: no longer LS+D */
                cause = endHere;
                break;
            }
            dNew = sampling_cosine_hemisphere(sf, uA, uB);
            for (int c = 0; c < 3; ++c) phi[c] = phi[c] * M.rhoD[c] / pd;
            flags |= PCL_PHOTON_AFTER_DIFFUSE;
        } else if (z < pd + ps) {
            for (int c = 0; c < 3; ++c) phi[c] = phi[c] * M.rhoS[c] / ps;
            flags |= PCL_PHOTON_AFTER_SPECULAR;
            if (M.specular == PCL_SPECULAR_MIRROR) {
                dNew = sampling_reflect(d, sf);
            } else if (M.specular == PCL_SPECULAR_GLOSSY) {
                const float e = M.exponent;
                dNew = sampling_phong_lobe(sampling_reflect(d, sf), e, uA, uB);
                const float cosOut = sampling_dot(dNew, sf);
                if (!(cosOut > 0.0f)) {
                    cause = endHere;
                    break;
                }
                for (int c = 0; c < 3; ++c) phi[c] = phi[c] * (e + 2.0f) / (e + 1.0f) * cosOut;
            } else { /* dielectric: n is the outside normal */
                const bool entering = dn < 0.0f;
                const float eta = entering ? 1.0f / M.ior : M.ior;
                const float cosI = fabs(sampling_dot(d, nsh));
                const float F = sampling_fresnel_dielectric(cosI, eta);
                if (uF < F)
                    dNew = sampling_reflect(d, sf);
                else {
                    dNew = sampling_refract(d, sf, cosI, eta);
                    refracted = true;
                }
            }
        } else {
            cause = endHere;
            break;
        }
        if (smooth) {
            /* A refraction must cross the geometric surface, anything else stay on the photon's
             * side; then the adjoint factor for scattering with the shading normal
             * (host/reference/light_tracer.cpp). */
            const float side = sampling_dot(dNew, n) * dn;
            if (refracted ? !(side > 0.0f) : !(side < 0.0f)) {
                cause = endHere;
                break;
            }
            const float adj = shading_adjoint(nsh, n, sampling_v3(-d.x, -d.y, -d.z), dNew);
            for (int c = 0; c < 3; ++c) phi[c] = phi[c] * adj;
        }
        if (b >= params.maxDepth) {
            cause = PCL_END_MAX_DEPTH;
            break;
        }

        /* Through the surface (refraction): the medium on the other side. */
        if (params.hasMedia && sampling_dot(dNew, n) * dn > 0.0f)
            medium = dn < 0.0f ? primMedia[hit.prim].inside : primMedia[hit.prim].outside;

        /* 3. Spawn off the side the new direction leaves by. */
        const float eps = params.rayEpsilon;
        const PclV3 ns = sampling_dot(dNew, nf) > 0.0f ? nf : sampling_v3(-nf.x, -nf.y, -nf.z);
        o = sampling_v3(p.x + ns.x * eps, p.y + ns.y * eps, p.z + ns.z * eps);
        d = dNew;
    }
    counts[i] = count;
    ends[i] = b | (cause << 8);
    if (params.hasMedia) volumeCounts[i] = volumeCount;
}

__kernel void trace_photons_global(const PclPhotonParams params, __global const PclPhotonRay* rays,
                                   __global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                                   __global const PclSphere* spheres, __global const PclPrimInfo* primInfo,
                                   __global const PclMaterial* materials, __global PclPhoton* slots,
                                   __global uint* counts, __global uint* ends,
                                   __global const PclMedium* media, __global const PclPrimMedium* primMedia,
                                   __global const int* lightMedia, __global PclPhoton* volumeSlots,
                                   __global uint* volumeCounts, __global const PclMaterialTextures* materialTextures,
                                   __global const float* texels, __global const PclTriangleUv* triangleUvs,
                                   __global const PclTriangleNormals* triangleNormals,
                                   __global const PclNormalMap* normalMaps,
                                   __global const PclTriangleTangents* triangleTangents) {
    trace_path(params, false, rays, nodes, packets, spheres, primInfo, materials, slots, counts, ends, media,
               primMedia, lightMedia, volumeSlots, volumeCounts, materialTextures, texels, triangleUvs,
               triangleNormals, normalMaps, triangleTangents);
}

__kernel void trace_photons_caustic(const PclPhotonParams params, __global const PclPhotonRay* rays,
                                    __global const PclBvhNode* nodes, __global const PclTriPacket* packets,
                                    __global const PclSphere* spheres, __global const PclPrimInfo* primInfo,
                                    __global const PclMaterial* materials, __global PclPhoton* slots,
                                    __global uint* counts, __global uint* ends,
                                    __global const PclMedium* media, __global const PclPrimMedium* primMedia,
                                    __global const int* lightMedia, __global PclPhoton* volumeSlots,
                                    __global uint* volumeCounts, __global const PclMaterialTextures* materialTextures,
                                    __global const float* texels, __global const PclTriangleUv* triangleUvs,
                                    __global const PclTriangleNormals* triangleNormals,
                                    __global const PclNormalMap* normalMaps,
                                    __global const PclTriangleTangents* triangleTangents) {
    trace_path(params, true, rays, nodes, packets, spheres, primInfo, materials, slots, counts, ends, media,
               primMedia, lightMedia, volumeSlots, volumeCounts, materialTextures, texels, triangleUvs,
               triangleNormals, normalMaps, triangleTangents);
}
