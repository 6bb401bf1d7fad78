/* stratify.h: the 2D samples of one pixel's pass stratified together, by correlated
 * multi-jittered sampling (A. Kensler, "Correlated Multi-Jittered Sampling", Pixar Technical
 * Memo 13-01, 2013: its final `cmj` for any count N).
 *
 * An eye hit's final-gather rays see nearly the same hemisphere as the other eye samples of its
 * pixel, so the n² × N gather directions of a pixel's pass are one hemisphere integral sampled
 * n² N times. Independent directions leave the indirect part with 1/(n² N) of one ray's
 * variance; stratified together (each direction in its own cell of an m × ⌈N/m⌉ grid, and
 * N-stratified in v alone) they lose the part that varies between cells. Each sample is still
 * uniform in [0,1)² over the pattern p, so the estimate stays unbiased.
 *
 * Kensler's permute is a hash-based bijection of [0, l) (cycle walking over the next power of
 * two: fewer than two rounds on average, but as many as the slowest of a vector's lanes needs).
 * The kernels therefore read one pattern per pass from a table made on the host and shift it per
 * pixel (stratify_shifted); the twins permute each sample themselves. The jitters come from the
 * caller's Philox words.
 * Written in the common subset of C and OpenCL C (compat.h): the kernels and their twins call
 * this same code. */
#ifndef PCL_STRATIFY_H
#define PCL_STRATIFY_H

#include "compat.h"

PCL_INLINE pcl_u32 stratify_permute(pcl_u32 i, pcl_u32 l, pcl_u32 p) {
    pcl_u32 w = l - 1u;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    do {
        i ^= p;
        i *= 0xe170893du;
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i *= 0x0929eb3fu;
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i *= 1u | p >> 27;
        i *= 0x6935fa69u;
        i ^= (i & w) >> 11;
        i *= 0x74dcb303u;
        i ^= (i & w) >> 2;
        i *= 0x9e501cc3u;
        i ^= (i & w) >> 2;
        i *= 0xc860a3dfu;
        i &= w;
        i ^= i >> 5;
    } while (i >= l);
    return (i + p) % l;
}

/* m = ⌊√N⌋, the columns of a pattern of N (integers alone, bit by bit: the same on every
 * device); its rows are n = ⌈N/m⌉. */
PCL_INLINE pcl_u32 stratify_columns(pcl_u32 N) {
    pcl_u32 m = 0u;
    for (pcl_u32 bit = 1u << 15; bit != 0u; bit >>= 1)
        if ((m | bit) * (m | bit) <= N) m |= bit;
    return m;
}

/* m · n: the fine columns of u. */
PCL_INLINE pcl_u32 stratify_cells(pcl_u32 N) {
    const pcl_u32 m = stratify_columns(N);
    return m * ((N + m - 1u) / m);
}

/* Sample s of N's cell in pattern p: a = sx·n + sy, its column of the m·n fine columns of u, and
 * b, its row of N in v. */
PCL_INLINE void stratify_cmj_cell(pcl_u32 s, pcl_u32 N, pcl_u32 p, pcl_u32* a, pcl_u32* b) {
    const pcl_u32 m = stratify_columns(N);
    const pcl_u32 n = (N + m - 1u) / m;
    s = stratify_permute(s, N, p * 0x51633e2du);
    const pcl_u32 sx = stratify_permute(s % m, m, p * 0x68bc21ebu);
    const pcl_u32 sy = stratify_permute(s / m, n, p * 0x02e5be93u);
    *a = sx * n + sy;
    *b = s;
}

/* The sample in cell (a, b) of N (cells = stratify_cells(N)), jittered within it by jx, jy in
 * [0, 1): (u, v) in [0, 1)² (N < 2^24, so every count is exact as a float; clamped below 1
 * against rounding). */
PCL_INLINE void stratify_cell_sample(pcl_u32 a, pcl_u32 b, pcl_u32 cells, pcl_u32 N, pcl_f32 jx, pcl_f32 jy,
                                     pcl_f32* u, pcl_f32* v) {
    const pcl_f32 x = ((pcl_f32)a + jx) / (pcl_f32)cells;
    const pcl_f32 y = ((pcl_f32)b + jy) / (pcl_f32)N;
    const pcl_f32 below1 = 0x1.fffffep-1f;
    *u = x < below1 ? x : below1;
    *v = y < below1 ? y : below1;
}

/* One pass's pattern shared by every pixel, each pixel's copy shifted on the torus by its own
 * (su, sv) in [0, 1) (Cranley–Patterson rotation): the cell (a, b) of sample s of N (cells =
 * stratify_cells(N), computed once by the caller) comes from a
 * table made once per pass (stratify_cmj_cell), so a kernel pays a load and two adds instead of
 * three permutations whose cycle walking diverges across vector lanes. A shifted stratification
 * stays one on the torus, and over the shift every sample is uniform: unbiased as before, with the
 * same variance on cornell-spheres-point (indirect AOV, two seeds: 4.26e-4 against 4.21e-4 for a
 * fresh pattern per pixel). */
PCL_INLINE void stratify_shifted(pcl_u32 a, pcl_u32 b, pcl_u32 cells, pcl_u32 N, pcl_f32 jx, pcl_f32 jy, pcl_f32 su,
                                 pcl_f32 sv, pcl_f32* u, pcl_f32* v) {
    pcl_f32 x, y;
    stratify_cell_sample(a, b, cells, N, jx, jy, &x, &y);
    x = x + su;
    y = y + sv;
    x = x >= 1.0f ? x - 1.0f : x;
    y = y >= 1.0f ? y - 1.0f : y;
    const pcl_f32 below1 = 0x1.fffffep-1f;
    *u = x < below1 ? x : below1;
    *v = y < below1 ? y : below1;
}

#endif
