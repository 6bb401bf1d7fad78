/* accumulate.cl: what one eye sample adds to the pass's film (kernels/README.md, "Eye pass:
 * accumulate"), so that a chunk comes back to the host as 16 bytes a sample instead of its
 * 128-byte records and every part (on a GPU the read-back, not the kernels, set a pass's time).
 *
 * accumulate_samples — one eye record per work-item:
 * in:  params               PclAccumulateParams: the chunk's first pixel and sample in it, n²,
 *                           the image's width, the parts present, whether emitter spans are given
 *      hits[i]              PclEyeHit (eye_paths): emitted
 *      direct, caustic, indirect, volume0, volume1 [i]
 *                           PclRadiance parts (read only where params.parts names them)
 *      spans[2y], [2y + 1]  row y's pixels [begin, end) whose emitted light the emitter samples
 *                           give (read only when params.emitterSpans)
 * out: radiance[i]          rgb = emitted + direct + caustic + indirect + volume, added in float
 *                           in that order, the volume part itself as 0 + volume0 + volume1; the
 *                           emitted term is 0 inside a span. Not checked for finiteness here:
 *                           the host counts and drops non-finite samples as it adds them. */
#include "shared/types.h"

__kernel void accumulate_samples(const PclAccumulateParams params, __global const PclEyeHit* hits,
                                 __global const PclRadiance* direct, __global const PclRadiance* caustic,
                                 __global const PclRadiance* indirect, __global const PclRadiance* volume0,
                                 __global const PclRadiance* volume1, __global const int* spans,
                                 __global PclRadiance* radiance) {
    const uint i = (uint)get_global_id(0);
    if (i >= params.sampleCount) return;
    const uint pixel = params.firstPixel + (params.firstSubsample + i) / params.samplesPerPixel;
    float e[3] = {hits[i].emitted[0], hits[i].emitted[1], hits[i].emitted[2]};
    if (params.emitterSpans) {
        const int x = (int)(pixel % params.width), y = (int)(pixel / params.width);
        if (x >= spans[2 * y] && x < spans[2 * y + 1]) e[0] = e[1] = e[2] = 0.0f;
    }
    float d[3] = {0.0f, 0.0f, 0.0f}, c[3] = {0.0f, 0.0f, 0.0f}, n[3] = {0.0f, 0.0f, 0.0f};
    float v[3] = {0.0f, 0.0f, 0.0f};
    if (params.parts & PCL_ACCUMULATE_DIRECT) d[0] = direct[i].r, d[1] = direct[i].g, d[2] = direct[i].b;
    if (params.parts & PCL_ACCUMULATE_CAUSTIC) c[0] = caustic[i].r, c[1] = caustic[i].g, c[2] = caustic[i].b;
    if (params.parts & PCL_ACCUMULATE_INDIRECT) n[0] = indirect[i].r, n[1] = indirect[i].g, n[2] = indirect[i].b;
    if (params.parts & PCL_ACCUMULATE_VOLUME0) v[0] += volume0[i].r, v[1] += volume0[i].g, v[2] += volume0[i].b;
    if (params.parts & PCL_ACCUMULATE_VOLUME1) v[0] += volume1[i].r, v[1] += volume1[i].g, v[2] += volume1[i].b;
    PclRadiance out;
    out.r = e[0] + d[0] + c[0] + n[0] + v[0];
    out.g = e[1] + d[1] + c[1] + n[1] + v[1];
    out.b = e[2] + d[2] + c[2] + n[2] + v[2];
    out.a = 0.0f;
    radiance[i] = out;
}
