/* morton.h: the Morton code of a query's cell (query_order.cl and its host twin,
 * pipeline/query_order.cpp): bits 0..7 of each cell coordinate interleaved, x lowest. */
#ifndef PCL_MORTON_H
#define PCL_MORTON_H

#include "compat.h"

/* Bits 0..7 of v spread to every third bit. */
PCL_INLINE pcl_u32 morton_spread8(pcl_u32 v) {
    v &= 0xFFu;
    v = (v | (v << 16)) & 0x030000FFu;
    v = (v | (v << 8)) & 0x0300F00Fu;
    v = (v | (v << 4)) & 0x030C30C3u;
    v = (v | (v << 2)) & 0x09249249u;
    return v;
}

PCL_INLINE pcl_u32 morton_key8(pcl_u32 ix, pcl_u32 iy, pcl_u32 iz) {
    return morton_spread8(ix) | morton_spread8(iy) << 1 | morton_spread8(iz) << 2;
}

#endif /* PCL_MORTON_H */
