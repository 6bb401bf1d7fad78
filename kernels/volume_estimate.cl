/* volume_estimate.cl: the beam radiance estimate (Jarosz, Zwicker & Jensen 2008) along
 * the eye's medium segments from one volume photon map (kernels/README.md, "volume_estimate").
 * One work-item per eye record.
 *
 * in:  params                       PclVolumeEstimateParams: the grid, r, the kernel, the skips
 *      segments[k*sampleCount + i]  PclVolumeSegment, k < segmentCounts[i] (≤ maxSegments)
 *      segmentCounts[i]
 *      media[]                      PclMedium: σa, σs, g
 *      photons[]                    the volume map (PCL_PHOTON_VOLUME records), in map order
 *      points[], cellStart[], cellEnd[]
 *                                   its hash grid (hashgrid.cl): sorted (x, y, z, photon index)
 *                                   and per hash the [start, end) of that order
 * out: volume[i]                    Σ_k throughput_k × L_k (rgb; a = 0)
 *
 * The segment is marched in steps of one cell: step s covers t ∈ [s h, min((s+1) h, ℓ)] and
 * reads the cells of its end points' bounding box grown by r; a photon counts in the step whose
 * interval holds its projection t_p, and only through its own cell, so exactly once. */
#pragma OPENCL FP_CONTRACT OFF
#include "shared/types.h"
#include "shared/sampling.h"

#define PCL_VOLUME_COORD_LIMIT 1.0e9f

/* ⌊(p − origin) · invCellSize⌋ clamped to ±1e9, as hashgrid.cl's grid_coord. */
inline int volume_grid_coord(float p, float origin, float invCellSize) {
    const float c = floor((p - origin) * invCellSize);
    return (int)clamp(c, -PCL_VOLUME_COORD_LIMIT, PCL_VOLUME_COORD_LIMIT);
}

inline uint volume_grid_hash(int ix, int iy, int iz, uint tableSize) {
    const uint h = ((uint)ix * 73856093u) ^ ((uint)iy * 19349663u) ^ ((uint)iz * 83492791u);
    return h & (tableSize - 1u);
}

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

/* L of one segment (rgb into l[]). */
inline void volume_segment_estimate(const PclVolumeEstimateParams params, const PclVolumeSegment seg,
                                     const PclMedium m, __global const PclPhoton* photons,
                                     __global const float4* points, __global const uint* cellStart,
                                     __global const uint* cellEnd, float l[3]) {
    l[0] = l[1] = l[2] = 0.0f;
    if (!(seg.length > 0.0f) || params.photonCount == 0u) return;
    const float sigmaT[3] = {m.sigmaA[0] + m.sigmaS[0], m.sigmaA[1] + m.sigmaS[1], m.sigmaA[2] + m.sigmaS[2]};
    const float h = params.cellSize;
    const float r = params.radius;
    const uint steps = (uint)ceil(seg.length / h);
    for (uint s = 0u; s < steps; ++s) {
        const float t0 = (float)s * h;
        const float tn = (float)(s + 1u) * h;
        const int last = s + 1u >= steps;
        const float t1 = last ? seg.length : tn;
        const float ax = seg.ox + t0 * seg.dx, ay = seg.oy + t0 * seg.dy, az = seg.oz + t0 * seg.dz;
        const float bx = seg.ox + t1 * seg.dx, by = seg.oy + t1 * seg.dy, bz = seg.oz + t1 * seg.dz;
        const int x0 = volume_grid_coord(fmin(ax, bx) - r, params.ox, params.invCellSize);
        const int x1 = volume_grid_coord(fmax(ax, bx) + r, params.ox, params.invCellSize);
        const int y0 = volume_grid_coord(fmin(ay, by) - r, params.oy, params.invCellSize);
        const int y1 = volume_grid_coord(fmax(ay, by) + r, params.oy, params.invCellSize);
        const int z0 = volume_grid_coord(fmin(az, bz) - r, params.oz, params.invCellSize);
        const int z1 = volume_grid_coord(fmax(az, bz) + r, params.oz, params.invCellSize);
        for (int iz = z0; iz <= z1; ++iz)
            for (int iy = y0; iy <= y1; ++iy)
                for (int ix = x0; ix <= x1; ++ix) {
                    const uint hash = volume_grid_hash(ix, iy, iz, params.tableSize);
                    const uint end = cellEnd[hash];
                    for (uint j = cellStart[hash]; j < end; ++j) {
                        const float4 q = points[j];
                        if (volume_grid_coord(q.x, params.ox, params.invCellSize) != ix ||
                            volume_grid_coord(q.y, params.oy, params.invCellSize) != iy ||
                            volume_grid_coord(q.z, params.oz, params.invCellSize) != iz)
                            continue;
                        const float vx = q.x - seg.ox, vy = q.y - seg.oy, vz = q.z - seg.oz;
                        const float tp = vx * seg.dx + vy * seg.dy + vz * seg.dz;
                        /* in this step's interval, and on the segment (a rounded (s + 1) h may
                         * pass ℓ before the last step) */
                        if (!(tp >= t0) || !(last ? tp <= t1 : tp < t1) || !(tp <= seg.length)) continue;
                        const float wx = vx - tp * seg.dx, wy = vy - tp * seg.dy, wz = vz - tp * seg.dz;
                        const float d2 = wx * wx + wy * wy + wz * wz;
                        if (!(d2 < params.radius2)) continue;
                        const PclPhoton ph = photons[as_uint(q.w)];
                        if (!volume_photon_counts(params, ph.packed)) continue;
                        float k = params.kernelScale;
                        if (params.kernelShape == PCL_BEAM_KERNEL_BIWEIGHT) {
                            const float u = 1.0f - d2 / params.radius2;
                            k = k * (u * u);
                        }
                        const PclV3 w = photon_dir_decode(ph.packed);
                        const float mu = w.x * seg.dx + w.y * seg.dy + w.z * seg.dz;
                        const float kp = k * volume_hg(mu, m.g);
                        float phi[3];
                        photon_rgbe_decode(ph.rgbe, &phi[0], &phi[1], &phi[2]);
                        for (int c = 0; c < 3; ++c) {
                            const float tr = sigmaT[c] > 0.0f ? exp(-sigmaT[c] * tp) : 1.0f;
                            l[c] += kp * tr * phi[c];
                        }
                    }
                }
    }
}

__kernel void volume_estimate_beams(const PclVolumeEstimateParams params, __global const PclVolumeSegment* segments,
                                    __global const uint* segmentCounts, __global const PclMedium* media,
                                    __global const PclPhoton* photons, __global const float4* points,
                                    __global const uint* cellStart, __global const uint* cellEnd,
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
        volume_segment_estimate(params, seg, media[seg.medium], photons, points, cellStart, cellEnd, l);
        for (int c = 0; c < 3; ++c) sum[c] += seg.throughput[c] * l[c];
    }
    PclRadiance out;
    out.r = sum[0];
    out.g = sum[1];
    out.b = sum[2];
    out.a = 0.0f;
    volume[i] = out;
}
