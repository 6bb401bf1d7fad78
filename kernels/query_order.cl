/* query_order.cl: a space-filling-curve order of estimate queries (pipeline/query_order.h).
 * Queries made in deposit order (the precomputed-irradiance points) or by random gather rays lie
 * all over the scene, so neighbouring work-items of a search walk different parts of the tree
 * and the searches wait on memory. Sorted by the Morton code of their cell, neighbouring
 * work-items read the same nodes and photons; the results are the same, only their order.
 *
 * query_order_keys     in:  queries[count] (PclEstimateQuery), invCell (1 / the cell's side)
 *                      out: keys[j] = Morton code of query j's cell, 8 bits per axis (cell
 *                           coordinates wrap modulo 256: a wrap only costs coherence), values[j] = j
 * (radix sort of (keys, values), 24 bits)
 * query_order_gather   in:  queries, order[count]   out: sorted[s] = queries[order[s]]
 * query_order_scatter  in:  sortedResults[s·m .. s·m + m) (m float4 per record), order
 *                      out: results[order[s]·m ..] = those m float4 */
#include "shared/types.h"
#include "shared/morton.h"

/* (int) of a float beyond the int range is undefined: clamped first (NaN gives cell 0). */
inline uint query_order_cell(float x, float invCell) {
    const float c = floor(x * invCell);
    return (uint)(int)(c == c ? clamp(c, -1.0e9f, 1.0e9f) : 0.0f);
}

__kernel void query_order_keys(__global const PclEstimateQuery* queries, uint count, float invCell,
                               __global uint* keys, __global uint* values) {
    const uint j = (uint)get_global_id(0);
    if (j >= count) return;
    const PclEstimateQuery q = queries[j];
    keys[j] = morton_key8(query_order_cell(q.x, invCell), query_order_cell(q.y, invCell),
                          query_order_cell(q.z, invCell));
    values[j] = j;
}

__kernel void query_order_gather(__global const PclEstimateQuery* queries, __global const uint* order, uint count,
                                 __global PclEstimateQuery* sorted) {
    const uint s = (uint)get_global_id(0);
    if (s >= count) return;
    sorted[s] = queries[order[s]];
}

__kernel void query_order_scatter(__global const float4* sortedResults, __global const uint* order, uint count,
                                  uint m, __global float4* results) {
    const uint s = (uint)get_global_id(0);
    if (s >= count) return;
    const size_t to = (size_t)order[s] * m, from = (size_t)s * m;
    for (uint c = 0u; c < m; ++c) results[to + c] = sortedResults[from + c];
}
