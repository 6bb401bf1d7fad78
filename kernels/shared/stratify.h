/* stratify.h: the 2D samples of one pixel's pass stratified together, by correlated
 * multi-jittered sampling (A. Kensler, "Correlated Multi-Jittered Sampling", Pixar Technical
 * Memo 13-01, 2013: its final `cmj` for any count N).
 *
 * An eye hit's final-gather rays see nearly the same hemisphere as the other eye samples of its
 * pixel, so the n² × N gather directions of a pixel's pass are one hemisphere integral sampled
 * n² N times. Independent directions leave the indirect part with 1/(n² N) of one ray's
 * variance; stratified together (each direction in its own cell of an m × ⌈N/m⌉ grid, and
 * N-stratified in v alone) they lose the part that varies between cells. Each sample is still
 * uniform in [0,1)² over the pattern p (a fresh one per pixel and pass), so the estimate stays
 * unbiased.
 *
 * Kensler's permute is a hash-based bijection of [0, l) (cycle walking over the next power of
 * two: fewer than two rounds on average). The jitters come from the caller's Philox words.
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

/* Sample s of N (s < N) of pattern p, jittered within its cell by jx, jy in [0, 1): (u, v) in
 * [0, 1)². m = ⌊√N⌋ columns of n = ⌈N/m⌉ rows (N < 2^24, so every count is exact as a float; the
 * result is clamped below 1 against the division's rounding). */
PCL_INLINE void stratify_cmj(pcl_u32 s, pcl_u32 N, pcl_u32 p, pcl_f32 jx, pcl_f32 jy, pcl_f32* u, pcl_f32* v) {
    pcl_u32 m = 0u; /* ⌊√N⌋ bit by bit: integers alone, the same on every device */
    for (pcl_u32 bit = 1u << 15; bit != 0u; bit >>= 1)
        if ((m | bit) * (m | bit) <= N) m |= bit;
    const pcl_u32 n = (N + m - 1u) / m;
    s = stratify_permute(s, N, p * 0x51633e2du);
    const pcl_u32 sx = stratify_permute(s % m, m, p * 0x68bc21ebu);
    const pcl_u32 sy = stratify_permute(s / m, n, p * 0x02e5be93u);
    const pcl_f32 a = ((pcl_f32)sx + ((pcl_f32)sy + jx) / (pcl_f32)n) / (pcl_f32)m;
    const pcl_f32 b = ((pcl_f32)s + jy) / (pcl_f32)N;
    const pcl_f32 below1 = 0x1.fffffep-1f;
    *u = a < below1 ? a : below1;
    *v = b < below1 ? b : below1;
}

#endif
