// Binned SAH builder. Each node bins its primitives' centroids into `bins` slabs along all
// three axes, sweeps the bins for the split with the lowest surface area heuristic
//   C = C_trav + (A_L C_L + A_R C_R) / A,   C_X = packets of 4 triangles + spheres in X,
// and stops when a leaf is no dearer than the best split. Where SAH cannot split (all centroids
// equal, e.g. many identical triangles) or the tree grows too deep, it falls back to an object
// median split, so the depth stays bounded. The two halves of large nodes are built on separate
// threads.
#include "geometry/bvh_build.h"

#include <algorithm>
#include <array>
#include <thread>

#include "geometry/scene_geometry.h"

namespace pcl {
namespace {

constexpr int kMaxBins = 32;
// Beyond this depth SAH gives way to median splits, which halve the count every level.
constexpr int kSahDepthLimit = 48;
// Nodes with more primitives than this hand one child to a new thread (while threads remain).
constexpr uint32_t kParallelThreshold = 50000;

// Binning touches every primitive of every node three times (once per axis); doing its box
// arithmetic on 4-wide vectors (GCC/Clang vector extensions, SSE on x86, NEON on ARM) instead
// of Vec3 halves the build time of a 1M-triangle mesh.
typedef float F4 __attribute__((vector_size(16)));
typedef int I4 __attribute__((vector_size(16)));
inline F4 min4(F4 a, F4 b) { return a < b ? a : b; }
inline F4 max4(F4 a, F4 b) { return a > b ? a : b; }
inline F4 splat(float x) { return F4{x, x, x, x}; }
inline F4 toF4(Vec3 v) { return F4{v.x, v.y, v.z, 0.0f}; }
inline Vec3 toVec3(F4 v) { return {v[0], v[1], v[2]}; }

struct Box4 {
    F4 lo = splat(INFINITY), hi = splat(-INFINITY);  // empty
    void extend(const Box4& b) {
        lo = min4(lo, b.lo);
        hi = max4(hi, b.hi);
    }
    void extend(F4 p) {
        lo = min4(lo, p);
        hi = max4(hi, p);
    }
    Bounds3 bounds() const { return {toVec3(lo), toVec3(hi)}; }
    float surfaceArea() const { return bounds().surfaceArea(); }
};

struct Bin {
    Box4 box;
    uint32_t triangles = 0, spheres = 0;
};

class Builder {
public:
    Builder(const std::vector<Bounds3>& boxes, uint32_t triangleCount, const BvhBuildOptions& o)
        : triangleCount_(triangleCount), bins_(std::clamp(o.bins, 2, kMaxBins)), traversalCost_(o.traversalCost),
          maxLeafTriangles_(static_cast<uint32_t>(std::clamp(o.maxLeafTriangles, 1, int(kMaxLeafPrimitives)))) {
        boxes_.resize(boxes.size());
        centroids_.resize(boxes.size());
        for (size_t i = 0; i < boxes.size(); ++i) {
            // NaN or infinite coordinates: an empty box (it extends nothing) and a centroid at
            // the origin so binning stays in range; the primitive is still referenced once.
            if (isFinite(boxes[i].lo) && isFinite(boxes[i].hi)) {
                boxes_[i].lo = toF4(boxes[i].lo);
                boxes_[i].hi = toF4(boxes[i].hi);
                centroids_[i] = (boxes_[i].lo + boxes_[i].hi) * 0.5f;
            } else {
                centroids_[i] = splat(0.0f);
            }
        }
    }

    std::unique_ptr<BinaryNode> build(uint32_t* ids, uint32_t begin, uint32_t end, int depth, int threads,
                                      int& maxDepth) {
        auto node = std::make_unique<BinaryNode>();
        maxDepth = std::max(maxDepth, depth);
        Box4 box, cbox4;
        uint32_t triangles = 0;
        for (uint32_t i = begin; i < end; ++i) {
            uint32_t p = ids[i];
            box.extend(boxes_[p]);
            cbox4.extend(centroids_[p]);
            triangles += p < triangleCount_;
        }
        node->box = box.bounds();
        const Bounds3 cbox = cbox4.bounds();
        const uint32_t n = end - begin;
        const uint32_t spheres = n - triangles;
        if (n <= 1 || n <= maxLeafTriangles_) return makeLeaf(std::move(node), begin, n);

        // Best SAH split over all three axes, binned in one pass.
        int bestAxis = -1, bestBin = 0;
        float bestCost = INFINITY;
        Vec3 extent = cbox.extent();
        if (depth < kSahDepthLimit) bestSplit(ids, begin, end, cbox, bestAxis, bestBin, bestCost);
        float area = node->box.surfaceArea();
        float splitCost = traversalCost_ + (area > 0.0f ? bestCost / area : bestCost);
        if (n <= kMaxLeafPrimitives && leafCost(triangles, spheres) <= splitCost)
            return makeLeaf(std::move(node), begin, n);

        uint32_t mid;
        if (bestAxis >= 0) {
            float lo = cbox.lo[bestAxis];
            float scale = binScale(extent[bestAxis]);
            uint32_t* m = std::partition(ids + begin, ids + end, [&](uint32_t p) {
                return binOf(centroids_[p][bestAxis], lo, scale) <= bestBin;
            });  // the same float expression as binning, so every primitive lands as binned
            mid = static_cast<uint32_t>(m - ids);
        } else {
            // Object median along the widest centroid axis (any split if they all coincide).
            int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
            mid = begin + medianCount(n);
            std::nth_element(ids + begin, ids + mid, ids + end,
                             [&](uint32_t a, uint32_t b) { return centroids_[a][axis] < centroids_[b][axis]; });
        }
        if (mid == begin || mid == end) mid = begin + medianCount(n);  // never an empty child

        if (threads > 1 && n > kParallelThreshold) {
            int leftDepth = maxDepth, rightDepth = maxDepth;
            std::thread worker([&] { node->child[0] = build(ids, begin, mid, depth + 1, threads / 2, leftDepth); });
            node->child[1] = build(ids, mid, end, depth + 1, threads - threads / 2, rightDepth);
            worker.join();
            maxDepth = std::max(leftDepth, rightDepth);
        } else {
            node->child[0] = build(ids, begin, mid, depth + 1, 1, maxDepth);
            node->child[1] = build(ids, mid, end, depth + 1, 1, maxDepth);
        }
        return node;
    }

private:
    static std::unique_ptr<BinaryNode> makeLeaf(std::unique_ptr<BinaryNode> node, uint32_t begin, uint32_t n) {
        node->first = begin;
        node->count = n;
        return node;
    }

    // About half, rounded to whole packets of 4 so the median halves fill their packets.
    static uint32_t medianCount(uint32_t n) {
        uint32_t half = (n / 2 + 3) / 4 * 4;
        return half > 0 && half < n ? half : n / 2;
    }

    float binScale(float extent) const {
        // Slightly under bins/extent so the largest centroid lands in the last bin, not past it.
        return static_cast<float>(bins_) * (1.0f - 1e-6f) / extent;
    }
    int binOf(float c, float lo, float scale) const {
        int b = static_cast<int>((c - lo) * scale);
        return std::clamp(b, 0, bins_ - 1);
    }

    // The cheapest split: axis, last bin of the left side (axis -1 if none) and its
    // unnormalised cost A_L C_L + A_R C_R.
    void bestSplit(const uint32_t* ids, uint32_t begin, uint32_t end, const Bounds3& cbox, int& bestAxis, int& bestBin,
                   float& bestCost) const {
        Bin bins[3][kMaxBins];
        F4 scale;
        for (int a = 0; a < 3; ++a) {
            float e = cbox.extent()[a];
            scale[a] = e > 0.0f ? binScale(e) : 0.0f;  // a flat axis puts everything in bin 0
        }
        scale[3] = 0.0f;
        const F4 lo = toF4(cbox.lo);
        const I4 last = I4{bins_ - 1, bins_ - 1, bins_ - 1, bins_ - 1};
        for (uint32_t i = begin; i < end; ++i) {
            const uint32_t p = ids[i];
            const Box4& pb = boxes_[p];
            I4 b = __builtin_convertvector((centroids_[p] - lo) * scale, I4);
            b = b < 0 ? I4{0, 0, 0, 0} : b;
            b = b > last ? last : b;
            const bool tri = p < triangleCount_;
            for (int a = 0; a < 3; ++a) {
                Bin& bin = bins[a][b[a]];
                bin.box.extend(pb);
                bin.triangles += tri;
                bin.spheres += !tri;
            }
        }
        for (int a = 0; a < 3; ++a) {
            if (scale[a] == 0.0f) continue;
            // Right-to-left sweep: cost of the right side for each split position.
            float rightCost[kMaxBins];
            Box4 box;
            uint32_t t = 0, s = 0;
            for (int i = bins_ - 1; i > 0; --i) {
                box.extend(bins[a][i].box);
                t += bins[a][i].triangles;
                s += bins[a][i].spheres;
                rightCost[i] = (t + s) ? box.surfaceArea() * leafCost(t, s) : -1.0f;
            }
            box = Box4{};
            t = s = 0;
            for (int i = 0; i < bins_ - 1; ++i) {
                box.extend(bins[a][i].box);
                t += bins[a][i].triangles;
                s += bins[a][i].spheres;
                if (t + s == 0 || rightCost[i + 1] < 0.0f) continue;
                float c = box.surfaceArea() * leafCost(t, s) + rightCost[i + 1];
                if (c < bestCost) {
                    bestCost = c;
                    bestAxis = a;
                    bestBin = i;
                }
            }
        }
    }

    std::vector<Box4> boxes_;    // per primitive; empty if not finite
    std::vector<F4> centroids_;  // per primitive; the origin if not finite
    uint32_t triangleCount_;
    int bins_;
    float traversalCost_;
    uint32_t maxLeafTriangles_;
};

}  // namespace

BinaryBvh buildBinaryBvh(const std::vector<Bounds3>& boxes, uint32_t triangleCount, const BvhBuildOptions& options) {
    BinaryBvh bvh;
    const auto n = static_cast<uint32_t>(boxes.size());
    bvh.order.resize(n);
    for (uint32_t i = 0; i < n; ++i) bvh.order[i] = i;
    if (n == 0) return bvh;
    Builder builder(boxes, triangleCount, options);
    int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    bvh.root = builder.build(bvh.order.data(), 0, n, 0, threads, bvh.depth);
    return bvh;
}

}  // namespace pcl
