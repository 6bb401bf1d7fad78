/* volume_estimate.cl: the beam radiance estimate (Jarosz, Zwicker & Jensen 2008) along
 * the eye's medium segments from one volume photon map (kernels/README.md, "volume_estimate").
 * One work-item per eye record.
 *
 * Each photon p has its own radius r_p ≤ r (the map's reach; a fixed-radius map gives every
 * photon r): it counts where the segment passes within r_p of it, with the 2-D kernel over its
 * own disc, K(d/r_p)/r_p² (Jarosz, Zwicker & Jensen 2008, eq. 22 with per-photon radii).
 *
 * volume_pack_photons, once per map, one work-item per grid entry j (the grid's sorted order):
 *      photons[], radius2[]         the volume map in map order and each photon's r_p²
 *      points[j]                    the grid's (x, y, z, photon index) (hashgrid.cl)
 *  out: beamPos[j]                  (x, y, z, r_p²); r_p² = −1 for a photon the skips drop
 *       beamDir[j]                  (w, kernelNorm / r_p²): the decoded direction and K's factor
 *       beamPower[j]                (ΔΦ rgb, 0)
 *   so the search reads three float4 in grid order, nothing in map order, and decodes nothing.
 * volume_estimate_beams, one work-item per eye record:
 *  in: params                       PclVolumeEstimateParams: the grid, the reach r, the kernel
 *      segments[k*sampleCount + i]  PclVolumeSegment, k < segmentCounts[i] (≤ maxSegments)
 *      segmentCounts[i]
 *      media[]                      PclMedium: σa, σs, g
 *      beamPos[], beamDir[], beamPower[], cellStart[], cellEnd[]
 *                                   the packed map and per hash the [start, end) of the grid
 *  out: volume[i]                   Σ_k throughput_k × L_k (rgb; a = 0)
 *
 * The grid's cells are of size r; the segment is walked in slabs one cell thick along its
 * dominant axis (volume_segment_estimate), a photon counts only through its own cell, so at most
 * once. */
#pragma OPENCL FP_CONTRACT OFF
#include "shared/types.h"
#include "shared/hash_grid.h"
#include "shared/sampling.h"

/* Henyey–Greenstein p(μ) = (1 − g²) / (4π (1 + g² − 2gμ)^{3/2}), the denominator written
 * (1 − g)² + 2g(1 − μ): no cancellation near the forward peak (μ → 1) for g → 1. */
inline float volume_hg(float mu, float g) {
    const float den = (1.0f - g) * (1.0f - g) + 2.0f * g * (1.0f - mu);
    return (1.0f - g * g) / (4.0f * M_PI_F * den * sqrt(den));
}

inline int volume_photon_counts(const PclVolumeEstimateParams params, uint packed) {
    if (params.skipDirect != 0u && ((packed >> PCL_PHOTON_BOUNCE_SHIFT) & 255u) == 0u) return 0;
    if (params.skipSpecularPaths != 0u && (packed & PCL_PHOTON_AFTER_SPECULAR) != 0u &&
        (packed & PCL_PHOTON_AFTER_DIFFUSE) == 0u)
        return 0;
    return 1;
}

/* photon_dir_decode's direction (shared/sampling.h: the centre of the (θ, φ) byte cell) by two
 * sincos calls instead of four sin/cos: the beam weighs hundreds of photons per segment. */
inline PclV3 volume_dir_decode(uint packed) {
    const float theta = ((float)(packed & 255u) + 0.5f) * (PCL_PI_F / 256.0f);
    const uint pb = (packed >> 8) & 255u;
    const int ps = pb >= 128u ? (int)pb - 256 : (int)pb;
    const float phi = ((float)ps + 0.5f) * (PCL_PI_F / 128.0f);
    float ct, cp;
    const float st = sincos(theta, &ct);
    const float sp = sincos(phi, &cp);
    return sampling_v3(st * cp, st * sp, ct);
}

/* One packed record (volume_pack_photons) per grid entry. */
__kernel void volume_pack_photons(const PclVolumeEstimateParams params, __global const PclPhoton* photons,
                                  __global const float* radius2, __global const float4* points,
                                  __global float4* beamPos, __global float4* beamDir, __global float4* beamPower) {
    const uint j = (uint)get_global_id(0);
    if (j >= params.photonCount) return;
    const float4 q = points[j];
    const uint idx = as_uint(q.w);
    const PclPhoton ph = photons[idx];
    const int counts = volume_photon_counts(params, ph.packed);
    const float r2 = radius2[idx];
    beamPos[j] = (float4)(q.x, q.y, q.z, counts ? r2 : -1.0f);
    const PclV3 w = volume_dir_decode(ph.packed);
    beamDir[j] = (float4)(w.x, w.y, w.z, params.kernelNorm / r2);
    float phi[3];
    photon_rgbe_decode(ph.rgbe, &phi[0], &phi[1], &phi[2]);
    beamPower[j] = counts ? (float4)(phi[0], phi[1], phi[2], 0.0f) : (float4)(0.0f);
}

/* The weight of entry j found in cell (ix, iy, iz): counted when the cell is its own (hash
 * collisions, and a cell reached through two hashes), its projection lies on the segment and it
 * is within its own r_p of it. */
inline void volume_add_photon(const PclVolumeEstimateParams params, const PclVolumeSegment seg, const PclMedium m,
                              const float sigmaT[3], __global const float4* beamDir,
                              __global const float4* beamPower, const float4 q, uint j, int ix, int iy, int iz,
                              float l[3]) {
    const float vx = q.x - seg.ox, vy = q.y - seg.oy, vz = q.z - seg.oz;
    const float tp = vx * seg.dx + vy * seg.dy + vz * seg.dz;
    if (!(tp >= 0.0f) || !(tp <= seg.length)) return;
    const float wx = vx - tp * seg.dx, wy = vy - tp * seg.dy, wz = vz - tp * seg.dz;
    const float d2 = wx * wx + wy * wy + wz * wz;
    if (!(d2 < q.w)) return;
    /* Last, for the few within reach: most candidates fail the cheaper tests above. */
    if (hash_grid_coord(q.x, params.ox, params.invCellSize) != ix ||
        hash_grid_coord(q.y, params.oy, params.invCellSize) != iy ||
        hash_grid_coord(q.z, params.oz, params.invCellSize) != iz)
        return;
    const float4 w = beamDir[j];
    float k = w.w;
    if (params.kernelShape == PCL_BEAM_KERNEL_BIWEIGHT) {
        const float u = 1.0f - d2 / q.w;
        k = k * (u * u);
    }
    const float mu = w.x * seg.dx + w.y * seg.dy + w.z * seg.dz;
    const float kp = k * volume_hg(mu, m.g);
    const float4 phi = beamPower[j];
    /* A grey medium (the common case) needs one exponential, not three. */
    const float tr0 = sigmaT[0] > 0.0f ? exp(-sigmaT[0] * tp) : 1.0f;
    const bool grey = sigmaT[1] == sigmaT[0] && sigmaT[2] == sigmaT[0];
    const float tr1 = grey ? tr0 : (sigmaT[1] > 0.0f ? exp(-sigmaT[1] * tp) : 1.0f);
    const float tr2 = grey ? tr0 : (sigmaT[2] > 0.0f ? exp(-sigmaT[2] * tp) : 1.0f);
    l[0] += kp * tr0 * phi.x;
    l[1] += kp * tr1 * phi.y;
    l[2] += kp * tr2 * phi.z;
}

/* L of one segment (rgb into l[]). The search walks the grid in slabs of one cell along the
 * segment's dominant axis: a photon within r of the segment, its projection on it, lies in a slab
 * whose stretch of the segment (the part whose dominant coordinate is within r of the slab) is
 * within r of it on the other two axes, so each slab visits the cells of that stretch's box grown
 * by r, and each photon is found once: in its own cell, in its own slab. */
inline void volume_segment_estimate(const PclVolumeEstimateParams params, const PclVolumeSegment seg,
                                     const PclMedium m, __global const float4* beamPos,
                                     __global const float4* beamDir, __global const float4* beamPower,
                                     __global const uint* cellStart,
                                     __global const uint* cellEnd, float l[3]) {
    l[0] = l[1] = l[2] = 0.0f;
    if (!(seg.length > 0.0f) || params.photonCount == 0u) return;
    const float sigmaT[3] = {m.sigmaA[0] + m.sigmaS[0], m.sigmaA[1] + m.sigmaS[1], m.sigmaA[2] + m.sigmaS[2]};
    const float r = params.radius;
    const float o[3] = {seg.ox, seg.oy, seg.oz}, d[3] = {seg.dx, seg.dy, seg.dz};
    const float origin[3] = {params.ox, params.oy, params.oz};
    const float adx = fabs(seg.dx), ady = fabs(seg.dy), adz = fabs(seg.dz);
    const int a = (adx >= ady && adx >= adz) ? 0 : (ady >= adz ? 1 : 2);
    const int b = a == 0 ? 1 : 0, c2 = a == 2 ? 1 : 2;
    const float e = o[a] + seg.length * d[a];
    const int s0 = hash_grid_coord(fmin(o[a], e) - r, origin[a], params.invCellSize);
    const int s1 = hash_grid_coord(fmax(o[a], e) + r, origin[a], params.invCellSize);
    /* The dominant component is at least 1/√3 of a unit vector: never 0 on a segment that moves. */
    const float invDa = 1.0f / d[a];
    for (int sa = s0; sa <= s1; ++sa) {
        /* The slab [A0, A1]; the segment's stretch whose dominant coordinate is within r of it. */
        const float A0 = origin[a] + (float)sa * params.cellSize, A1 = A0 + params.cellSize;
        float tA = (A0 - r - o[a]) * invDa, tB = (A1 + r - o[a]) * invDa;
        if (tA > tB) {
            const float tmp = tA;
            tA = tB;
            tB = tmp;
        }
        tA = fmax(tA, 0.0f);
        tB = fmin(tB, seg.length);
        if (!(tA <= tB)) continue;
        const float pb0 = o[b] + tA * d[b], pb1 = o[b] + tB * d[b];
        const float pc0 = o[c2] + tA * d[c2], pc1 = o[c2] + tB * d[c2];
        const int b0 = hash_grid_coord(fmin(pb0, pb1) - r, origin[b], params.invCellSize);
        const int b1 = hash_grid_coord(fmax(pb0, pb1) + r, origin[b], params.invCellSize);
        const int c0 = hash_grid_coord(fmin(pc0, pc1) - r, origin[c2], params.invCellSize);
        const int c1 = hash_grid_coord(fmax(pc0, pc1) + r, origin[c2], params.invCellSize);
        for (int ic = c0; ic <= c1; ++ic)
            for (int ib = b0; ib <= b1; ++ib) {
                int cell[3];
                cell[a] = sa;
                cell[b] = ib;
                cell[c2] = ic;
                const uint hash = hash_grid_hash(cell[0], cell[1], cell[2], params.tableSize);
                const uint end = cellEnd[hash];
                for (uint j = cellStart[hash]; j < end; ++j)
                    volume_add_photon(params, seg, m, sigmaT, beamDir, beamPower, beamPos[j], j, cell[0], cell[1],
                                      cell[2], l);
            }
    }
}

__kernel void volume_estimate_beams(const PclVolumeEstimateParams params, __global const PclVolumeSegment* segments,
                                    __global const uint* segmentCounts, __global const PclMedium* media,
                                    __global const float4* beamPos, __global const float4* beamDir,
                                    __global const float4* beamPower, __global const uint* cellStart, __global const uint* cellEnd,
                                    __global PclRadiance* volume) {
    const uint i = (uint)get_global_id(0);
    if (i >= params.sampleCount) return;
    uint count = segmentCounts[i];
    count = count < params.maxSegments ? count : params.maxSegments;
    float sum[3] = {0.0f, 0.0f, 0.0f};
    for (uint k = 0u; k < count; ++k) {
        const PclVolumeSegment seg = segments[(size_t)k * params.sampleCount + i];
        if (seg.medium < 0 || seg.medium >= (int)params.mediumCount) continue;
        float l[3];
        volume_segment_estimate(params, seg, media[seg.medium], beamPos, beamDir, beamPower, cellStart, cellEnd, l);
        for (int c = 0; c < 3; ++c) sum[c] += seg.throughput[c] * l[c];
    }
    PclRadiance out;
    out.r = sum[0];
    out.g = sum[1];
    out.b = sum[2];
    out.a = 0.0f;
    volume[i] = out;
}
