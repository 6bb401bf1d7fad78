// CPU twin of the k-nearest-neighbour search (kernels/README.md, "Photon maps", knn): brute
// force over every photon of the map, written from the spec. Per query: the k photons with
// squared distance ≤ maxRadius2, in ascending (squared distance, photon index) order, the
// squared distance computed in float as ((px−qx)² + (py−qy)²) + (pz−qz)²; r² = the largest
// returned, 0 when none.
#pragma once
#include <cstdint>
#include <vector>

#include "shared/types.h"

namespace pcl {

struct ReferenceKnn {
    uint32_t stride = 0;            // slots per query: the largest k
    std::vector<uint32_t> counts;   // per query
    std::vector<uint32_t> indices;  // queries × stride; PCL_NO_HIT past count
    std::vector<float> dist2;       // queries × stride; 0 past count
    std::vector<float> radius2;     // per query
};

// threads: 0 = all cores.
ReferenceKnn referenceKnnBruteForce(const std::vector<PclPhoton>& map, const std::vector<PclKnnQuery>& queries,
                                    unsigned threads = 0);

}  // namespace pcl
