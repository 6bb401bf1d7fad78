/* probe.cl: what the device compiler makes of the shared headers, for tests/stages/probe_test.cpp.
 *   probe_sizes:  sizeof of every shared buffer struct, in the order of PCL_SHARED_STRUCTS.
 *   probe_philox: Philox4x32-10 on the device, for the known-answer test. */
#include "shared/struct_list.h"
#include "shared/rng.h"

__kernel void probe_sizes(__global uint* sizes) {
    uint i = 0;
#define PCL_PROBE_SIZE(T) sizes[i++] = (uint)sizeof(T);
    PCL_SHARED_STRUCTS(PCL_PROBE_SIZE)
#undef PCL_PROBE_SIZE
}

/* Work-item g: out[4g..4g+3] = philox4x32_10(ctr[4g..4g+3], key[2g..2g+1]). */
__kernel void probe_philox(__global const uint* ctr, __global const uint* key, __global uint* out) {
    const size_t g = get_global_id(0);
    uint c[4], k[2], o[4];
    for (int i = 0; i < 4; ++i) c[i] = ctr[4 * g + i];
    k[0] = key[2 * g];
    k[1] = key[2 * g + 1];
    rng_philox4x32_10(c, k, o);
    for (int i = 0; i < 4; ++i) out[4 * g + i] = o[i];
}

/* Work-item g: out[g] = rng_next_u32 for dimension g of (seed, path, bounce, stream), through
 * PclRng, so the test checks the device's counter layout against the host's. */
__kernel void probe_rng_stream(ulong seed, uint path, uint bounce, uint stream, __global uint* out) {
    const uint g = (uint)get_global_id(0);
    PclRng r = rng_start(seed, path, bounce, stream);
    uint w = 0;
    for (uint d = 0; d <= g; ++d) w = rng_next_u32(&r);
    out[g] = w;
}
