/* kd_buckets.h: the bucket layout of a left-balanced heap kd-tree's last three levels, shared by
 * the kNN search (knn.cl) and the precomputed-irradiance lookup (precomputed_irradiance.cl).
 *
 * A tree of n nodes has L = ⌊log2 n⌋ + 1 levels; its buckets are rooted on level D = max(L − 3, 0),
 * bucketFirst = 2^D − 1 (host: pipeline/knn.h knnBucketFirst). Bucket b (root r = bucketFirst + b)
 * holds the nodes of r's subtree that exist (< n), breadth first: r; 2r+1, 2r+2; 4r+3 .. 4r+6.
 * In a left-balanced heap those are the first `count` of the 7 (the last level fills from the
 * left), so a bucket is stored compactly: `rows` arrays of `count` floats each, one after the
 * other, the buckets one after the other (no empty slots: the layout costs n floats per row,
 * plus 8 of padding for the last bucket's 8-wide loads). The searches load each row with vload8
 * and ignore lanes ≥ count. Counts and offsets follow from n and b alone. */
#ifndef PCL_KD_BUCKETS_H
#define PCL_KD_BUCKETS_H
#ifdef __OPENCL_VERSION__

/* Existing nodes of bucket b's subtree on its levels 1 and 2 before bucket b, and in it. */
inline uint kd_bucket_level_nodes(uint n, uint levelFirst, uint width, uint b) {
    const uint onLevel = n > levelFirst ? n - levelFirst : 0u;  /* nodes of that level that exist */
    return min(width * b, onLevel);
}

/* The first node of bucket b in storage order (the nodes of buckets 0 .. b−1). */
inline uint kd_bucket_offset(uint n, uint bucketFirst, uint b) {
    return b + kd_bucket_level_nodes(n, 2u * bucketFirst + 1u, 2u, b) +
           kd_bucket_level_nodes(n, 4u * bucketFirst + 3u, 4u, b);
}

inline uint kd_bucket_count(uint n, uint bucketFirst, uint b) {
    return kd_bucket_offset(n, bucketFirst, b + 1u) - kd_bucket_offset(n, bucketFirst, b);
}

/* Heap node h ≥ bucketFirst: its bucket and its slot (breadth-first position) in it. */
inline void kd_bucket_slot(uint h, uint bucketFirst, uint* bucket, uint* slot) {
    const uint lev = 31u - clz(h + 1u), levD = 31u - clz(bucketFirst + 1u);
    const uint t = lev - levD;                     /* 0, 1 or 2 levels below the root */
    const uint root = ((h + 1u) >> t) - 1u;
    *bucket = root - bucketFirst;
    *slot = (1u << t) - 1u + ((h + 1u) - ((root + 1u) << t));
}

#endif
#endif /* PCL_KD_BUCKETS_H */
