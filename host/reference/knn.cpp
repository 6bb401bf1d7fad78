#include "reference/knn.h"

#include <algorithm>
#include <utility>

#include "reference/parallel_for.h"

namespace pcl {

ReferenceKnn referenceKnnBruteForce(const std::vector<PclPhoton>& map, const std::vector<PclKnnQuery>& queries,
                                    unsigned threads) {
    ReferenceKnn r;
    uint32_t stride = 0;
    for (const PclKnnQuery& q : queries) stride = std::max(stride, q.k);
    r.stride = stride;
    const size_t nq = queries.size();
    r.counts.assign(nq, 0u);
    r.radius2.assign(nq, 0.0f);
    r.indices.assign(nq * stride, PCL_NO_HIT);
    r.dist2.assign(nq * stride, 0.0f);
    referenceParallelFor(nq, threads, [&](size_t qi) {
        const PclKnnQuery& q = queries[qi];
        std::vector<std::pair<float, uint32_t>> near;
        if (!(q.maxRadius2 > 0.0f)) return;  // an empty query (kernels/knn.cl): nothing found
        for (size_t i = 0; i < map.size(); ++i) {
            const float dx = map[i].x - q.x;
            const float dy = map[i].y - q.y;
            const float dz = map[i].z - q.z;
            const float xy = dx * dx + dy * dy;
            const float d2 = xy + dz * dz;
            if (d2 <= q.maxRadius2) near.emplace_back(d2, uint32_t(i));
        }
        const size_t keep = std::min<size_t>(near.size(), q.k);
        std::partial_sort(near.begin(), near.begin() + keep, near.end());  // pairs: (d², index) lexicographic
        for (size_t j = 0; j < keep; ++j) {
            r.indices[qi * stride + j] = near[j].second;
            r.dist2[qi * stride + j] = near[j].first;
        }
        r.counts[qi] = uint32_t(keep);
        r.radius2[qi] = keep ? near[keep - 1].first : 0.0f;
    });
    return r;
}

}  // namespace pcl
