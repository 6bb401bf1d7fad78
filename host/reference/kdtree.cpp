#include "reference/kdtree.h"

#include <algorithm>
#include <stdexcept>

#include "reference/sort.h"

namespace pcl {
namespace {

float coord(const PclPhoton& p, int axis) { return axis == 0 ? p.x : (axis == 1 ? p.y : p.z); }

struct Builder {
    const std::vector<PclPhoton>& in;
    ReferenceKdTree& out;

    // Photons idx[begin, end) form the subtree of heap node h.
    void build(std::vector<uint32_t>& idx, size_t begin, size_t end, size_t h) {
        const size_t n = end - begin;
        float lo[3], hi[3];
        for (int a = 0; a < 3; ++a) lo[a] = hi[a] = coord(in[idx[begin]], a);
        for (size_t k = begin + 1; k < end; ++k)
            for (int a = 0; a < 3; ++a) {
                const float c = coord(in[idx[k]], a);
                lo[a] = std::min(lo[a], c);
                hi[a] = std::max(hi[a], c);
            }
        int axis = 0;
        float extent = hi[0] - lo[0];
        for (int a = 1; a < 3; ++a)
            if (hi[a] - lo[a] > extent) {
                axis = a;
                extent = hi[a] - lo[a];
            }
        const uint32_t left = referenceKdLeftSize(uint32_t(n));
        // nth_element under a strict total order (key, index): the photon at `left` is the one a
        // full sort would put there, and the two sides hold the same photons as after the sort.
        std::nth_element(idx.begin() + begin, idx.begin() + begin + left, idx.begin() + end,
                         [&](uint32_t a, uint32_t b) {
                             const uint32_t ka = referenceFloatKey(coord(in[a], axis));
                             const uint32_t kb = referenceFloatKey(coord(in[b], axis));
                             return ka != kb ? ka < kb : a < b;
                         });
        const uint32_t m = idx[begin + left];
        PclPhoton p = in[m];
        p.packed = (p.packed & ~PCL_PHOTON_AXIS_MASK) | (uint32_t(axis) << PCL_PHOTON_AXIS_SHIFT);
        out.photons[h] = p;
        out.index[h] = m;
        if (left > 0) build(idx, begin, begin + left, 2 * h + 1);
        if (begin + left + 1 < end) build(idx, begin + left + 1, end, 2 * h + 2);
    }
};

}  // namespace

uint32_t referenceKdLeftSize(uint32_t n) {
    if (n <= 1) return 0;
    uint32_t h = 0;
    while ((n >> (h + 1)) != 0) ++h;  // h = ⌊log2 n⌋ ≥ 1
    const uint32_t half = 1u << (h - 1);
    return half - 1 + std::min(half, n - ((1u << h) - 1));
}

ReferenceKdTree referenceBuildKdTree(const std::vector<PclPhoton>& photons) {
    if (photons.size() >= (size_t(1) << 31)) throw std::invalid_argument("referenceBuildKdTree: too many photons");
    ReferenceKdTree tree;
    tree.photons.resize(photons.size());
    tree.index.resize(photons.size());
    if (photons.empty()) return tree;
    std::vector<uint32_t> idx(photons.size());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = uint32_t(i);
    Builder{photons, tree}.build(idx, 0, idx.size(), 0);
    return tree;
}

}  // namespace pcl
