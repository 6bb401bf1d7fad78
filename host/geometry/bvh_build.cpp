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

struct Bin {
    Bounds3 box;
    uint32_t triangles = 0, spheres = 0;
};

class Builder {
public:
    Builder(const std::vector<Bounds3>& boxes, uint32_t triangleCount, const BvhBuildOptions& o)
        : boxes_(boxes), triangleCount_(triangleCount),
          bins_(std::clamp(o.bins, 2, kMaxBins)), traversalCost_(o.traversalCost),
          maxLeafTriangles_(static_cast<uint32_t>(std::clamp(o.maxLeafTriangles, 1, int(kMaxLeafPrimitives)))) {
        centroids_.resize(boxes.size());
        for (size_t i = 0; i < boxes.size(); ++i) {
            Vec3 c = boxes[i].centre();
            // NaN or infinite coordinates: park the centroid at the origin so binning stays
            // in range; the primitive is still referenced once (and can never be hit).
            centroids_[i] = isFinite(c) ? c : Vec3(0.0f);
        }
    }

    std::unique_ptr<BinaryNode> build(uint32_t* ids, uint32_t begin, uint32_t end, int depth,
                                      int threads, int& maxDepth) {
        auto node = std::make_unique<BinaryNode>();
        maxDepth = std::max(maxDepth, depth);
        Bounds3 cbox;
        uint32_t triangles = 0;
        for (uint32_t i = begin; i < end; ++i) {
            uint32_t p = ids[i];
            if (isFinite(boxes_[p].lo) && isFinite(boxes_[p].hi)) node->box.extend(boxes_[p]);
            cbox.extend(centroids_[p]);
            triangles += p < triangleCount_;
        }
        const uint32_t n = end - begin;
        const uint32_t spheres = n - triangles;
        if (n <= 1 || n <= maxLeafTriangles_) return makeLeaf(std::move(node), begin, n);

        // Best SAH split over all three axes.
        int bestAxis = -1, bestBin = 0;
        float bestCost = INFINITY;
        Vec3 extent = cbox.extent();
        if (depth < kSahDepthLimit) {
            for (int axis = 0; axis < 3; ++axis) {
                if (!(extent[axis] > 0.0f)) continue;
                float cost;
                int bin = bestSplit(ids, begin, end, axis, cbox, cost);
                if (bin >= 0 && cost < bestCost) { bestCost = cost; bestAxis = axis; bestBin = bin; }
            }
        }
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
            });
            mid = static_cast<uint32_t>(m - ids);
        } else {
            // Object median along the widest centroid axis (any split if they all coincide).
            int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
            mid = begin + medianCount(n);
            std::nth_element(ids + begin, ids + mid, ids + end, [&](uint32_t a, uint32_t b) {
                return centroids_[a][axis] < centroids_[b][axis];
            });
        }
        if (mid == begin || mid == end) mid = begin + medianCount(n);  // never an empty child

        if (threads > 1 && n > kParallelThreshold) {
            int leftDepth = maxDepth, rightDepth = maxDepth;
            std::thread worker([&] {
                node->child[0] = build(ids, begin, mid, depth + 1, threads / 2, leftDepth);
            });
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
    static std::unique_ptr<BinaryNode> makeLeaf(std::unique_ptr<BinaryNode> node, uint32_t begin,
                                                uint32_t n) {
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

    // Returns the last bin of the left side of the cheapest split on `axis` (-1 if none) and
    // its unnormalised cost A_L C_L + A_R C_R.
    int bestSplit(const uint32_t* ids, uint32_t begin, uint32_t end, int axis, const Bounds3& cbox,
                  float& cost) const {
        std::array<Bin, kMaxBins> bins{};
        float lo = cbox.lo[axis];
        float scale = binScale(cbox.extent()[axis]);
        for (uint32_t i = begin; i < end; ++i) {
            uint32_t p = ids[i];
            Bin& b = bins[binOf(centroids_[p][axis], lo, scale)];
            if (isFinite(boxes_[p].lo) && isFinite(boxes_[p].hi)) b.box.extend(boxes_[p]);
            if (p < triangleCount_) ++b.triangles; else ++b.spheres;
        }
        // Right-to-left sweep: cost of the right side for each split position.
        std::array<float, kMaxBins> rightCost{};
        Bounds3 box;
        uint32_t t = 0, s = 0;
        for (int i = bins_ - 1; i > 0; --i) {
            box.extend(bins[i].box);
            t += bins[i].triangles;
            s += bins[i].spheres;
            rightCost[i] = (t + s) ? box.surfaceArea() * leafCost(t, s) : -1.0f;
        }
        box = Bounds3{};
        t = s = 0;
        int best = -1;
        cost = INFINITY;
        for (int i = 0; i < bins_ - 1; ++i) {
            box.extend(bins[i].box);
            t += bins[i].triangles;
            s += bins[i].spheres;
            if (t + s == 0 || rightCost[i + 1] < 0.0f) continue;
            float c = box.surfaceArea() * leafCost(t, s) + rightCost[i + 1];
            if (c < cost) { cost = c; best = i; }
        }
        return best;
    }

    const std::vector<Bounds3>& boxes_;
    std::vector<Vec3> centroids_;
    uint32_t triangleCount_;
    int bins_;
    float traversalCost_;
    uint32_t maxLeafTriangles_;
};

}  // namespace

BinaryBvh buildBinaryBvh(const std::vector<Bounds3>& boxes, uint32_t triangleCount,
                         const BvhBuildOptions& options) {
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
