/* rng.h: counter-based random numbers, Philox4x32-10.
 *
 * J. K. Salmon, M. A. Moraes, R. O. Dror, D. E. Shaw, "Parallel random numbers: as easy as
 * 1, 2, 3", SC 2011 (the Random123 library). A counter-based generator is a keyed bijection:
 * the number for (seed, path, bounce, dimension) is computed, not drawn from a sequence, so a
 * kernel work-item and its CPU twin get the same numbers in any order, on any device, with no
 * state to store between launches.
 *
 * Counter layout (indexed by seed, path, bounce and dimension: kernels/README.md, "Random numbers"):
 *   key = { seed_lo, seed_hi }             the 64-bit render seed
 *   ctr = { path, bounce, dim / 4, stream }
 * One Philox call gives four 32-bit words: dimensions 4b..4b+3 of a (path, bounce) pair.
 * `stream` separates uses that share path and bounce indices (photon tracing, camera paths,
 * final-gather rays, ...): see the PCL_RNG_STREAM_* values.
 *
 * Written in the common subset of C and OpenCL C (compat.h) so the host tests it without a
 * device and the twins call the same code. */
#ifndef PCL_RNG_H
#define PCL_RNG_H

#include "compat.h"

/* Philox4x32 constants (Random123 philox.h): round multipliers and Weyl key increments
 * (golden ratio and sqrt(3) - 1 in 0.32 fixed point). */
#define PCL_PHILOX_M0 0xD2511F53u
#define PCL_PHILOX_M1 0xCD9E8D57u
#define PCL_PHILOX_W0 0x9E3779B9u
#define PCL_PHILOX_W1 0xBB67AE85u

/* Streams: the fourth counter word. */
#define PCL_RNG_STREAM_PHOTON 0u
#define PCL_RNG_STREAM_CAMERA 1u
#define PCL_RNG_STREAM_GATHER 2u
#define PCL_RNG_STREAM_LIGHT 3u
#define PCL_RNG_STREAM_CAUSTIC 4u
#define PCL_RNG_STREAM_LIGHT_PATH 5u /* the host reference's light tracer (light path, pass) */
#define PCL_RNG_STREAM_EQUIANGULAR 6u /* the host reference path tracer's equiangular samples in media */
#define PCL_RNG_STREAM_EYE_MEDIUM 7u /* eye_paths: single scattering along the eye segments in media */
#define PCL_RNG_STREAM_CONNECT 8u /* connect_caustics: the lens point of caustic photon i's connection */
#define PCL_RNG_STREAM_EYE_SKY 9u /* eye_paths: a glossy hit's sample of the sky (path = pixel, bounce = k, block = hit) */
#define PCL_RNG_STREAM_TEST 0xFFFFFFFFu

/* The high word of a 32x32-bit product, by a 64-bit multiply on both sides rather than OpenCL's
 * mul_hi: PoCL 3.1 builds mul_hi(uint, uint) from 16-bit partial products (four multiplies and a
 * carry chain), about half of emit_photons' own time; the 64-bit form cut emit's device time by
 * a quarter to a third and trace_photons' by up to a fifth. GPU compilers turn it into their
 * native mul.hi. */
PCL_INLINE pcl_u32 rng_mulhi32(pcl_u32 a, pcl_u32 b) {
    return (pcl_u32)(((pcl_u64)a * (pcl_u64)b) >> 32);
}

/* Philox4x32-10: ten rounds, the key bumped between rounds (Random123 philox4x32_R, R = 10).
 * The arrays are private memory on the device (OpenCL 1.2 has no generic address space). */
PCL_INLINE void rng_philox4x32_10(const pcl_u32 ctr[4], const pcl_u32 key[2], pcl_u32 out[4]) {
    pcl_u32 c0 = ctr[0], c1 = ctr[1], c2 = ctr[2], c3 = ctr[3];
    pcl_u32 k0 = key[0], k1 = key[1];
    for (int round = 0; round < 10; ++round) {
        if (round > 0) {
            k0 += PCL_PHILOX_W0;
            k1 += PCL_PHILOX_W1;
        }
        const pcl_u32 hi0 = rng_mulhi32(PCL_PHILOX_M0, c0), lo0 = PCL_PHILOX_M0 * c0;
        const pcl_u32 hi1 = rng_mulhi32(PCL_PHILOX_M1, c2), lo1 = PCL_PHILOX_M1 * c2;
        c0 = hi1 ^ c1 ^ k0;
        c1 = lo1;
        c2 = hi0 ^ c3 ^ k1;
        c3 = lo0;
    }
    out[0] = c0;
    out[1] = c1;
    out[2] = c2;
    out[3] = c3;
}

/* A 32-bit word to a float in [0, 1): the top 24 bits, exactly representable, so the largest
 * value is 1 - 2^-24 and 1.0 never appears. */
PCL_INLINE pcl_f32 rng_u01(pcl_u32 x) {
    return (pcl_f32)(x >> 8) * 0x1p-24f;
}

/* The four words of block `block` for (seed, path, bounce, stream): dimensions 4*block .. +3. */
PCL_INLINE void rng_block(pcl_u64 seed, pcl_u32 path, pcl_u32 bounce, pcl_u32 block, pcl_u32 stream,
                          pcl_u32 out[4]) {
    pcl_u32 ctr[4];
    pcl_u32 key[2];
    ctr[0] = path;
    ctr[1] = bounce;
    ctr[2] = block;
    ctr[3] = stream;
    key[0] = (pcl_u32)seed;
    key[1] = (pcl_u32)(seed >> 32);
    rng_philox4x32_10(ctr, key, out);
}

/* One dimension on its own: uniform in [0, 1). Costs a whole Philox call; PclRng below shares
 * each call among four consecutive dimensions. */
PCL_INLINE pcl_f32 rng_uniform_at(pcl_u64 seed, pcl_u32 path, pcl_u32 bounce, pcl_u32 stream,
                                  pcl_u32 dim) {
    pcl_u32 w[4];
    rng_block(seed, path, bounce, dim >> 2, stream, w);
    return rng_u01(w[dim & 3u]);
}

/* Consecutive dimensions 0, 1, 2, ... of one (seed, path, bounce, stream): rng_next(&r) returns
 * exactly rng_uniform_at(seed, path, bounce, stream, d) for d = 0, 1, 2, ... */
typedef struct PclRng {
    pcl_u64 seed;
    pcl_u32 path, bounce, stream;
    pcl_u32 dim;      /* the next dimension to hand out */
    pcl_u32 word[4];  /* the block holding dimensions (dim & ~3) .. +3, valid when dim & 3 != 0 */
} PclRng;

PCL_INLINE PclRng rng_start(pcl_u64 seed, pcl_u32 path, pcl_u32 bounce, pcl_u32 stream) {
    PclRng r;
    r.seed = seed;
    r.path = path;
    r.bounce = bounce;
    r.stream = stream;
    r.dim = 0;
    r.word[0] = r.word[1] = r.word[2] = r.word[3] = 0;
    return r;
}

PCL_INLINE pcl_u32 rng_next_u32(PclRng* r) {
    if ((r->dim & 3u) == 0u) rng_block(r->seed, r->path, r->bounce, r->dim >> 2, r->stream, r->word);
    const pcl_u32 w = r->word[r->dim & 3u];
    r->dim += 1u;
    return w;
}

PCL_INLINE pcl_f32 rng_next(PclRng* r) {
    return rng_u01(rng_next_u32(r));
}

#endif /* PCL_RNG_H */
