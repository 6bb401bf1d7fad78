#include "geometry/bvh_collapse.h"

#include <algorithm>
#include <cmath>

#include "geometry/scene_geometry.h"

namespace pcl {
namespace {

// A child slot of a wide node before it is written: an interior binary node, or one kind of
// primitive from a binary leaf (a leaf holding triangles and spheres fills two slots).
struct Slot {
    const BinaryNode* node = nullptr;
    bool leaf = false, spheres = false;
};

class Collapser {
public:
    Collapser(const BinaryBvh& bvh, const CollapseSource& src, std::vector<PclBvhNode>& nodes,
              std::vector<PclTriPacket>& packets, std::vector<PclSphere>& spheres, BvhStats& stats)
        : bvh_(bvh), src_(src), nodes_(nodes), packets_(packets), spheres_(spheres), stats_(stats) {}

    void run() {
        nodes_.clear();
        packets_.clear();
        spheres_.clear();
        stats_.leaves = 0;
        stats_.triangles = 0;
        sah_ = 0.0;
        if (!bvh_.root) {
            nodes_.push_back(emptyNode());
            stats_.depth = 1;
            stats_.maxStack = 1;
            stats_.sahCost = 0.0;
            return;
        }
        rootArea_ = bvh_.root->box.surfaceArea();
        int stack = 0;
        emitNode(bvh_.root.get(), 1, stack);
        stats_.maxStack = std::max(1, stack);
        stats_.sahCost = sah_;
    }

private:
    static PclBvhNode emptyNode() {
        PclBvhNode n;
        // An empty slot's box is inverted (lo = +inf, hi = -inf): every slab test rejects it.
        for (int i = 0; i < PCL_BVH_WIDTH; ++i) {
            n.lox[i] = n.loy[i] = n.loz[i] = INFINITY;
            n.hix[i] = n.hiy[i] = n.hiz[i] = -INFINITY;
            n.child[i] = PCL_CHILD_EMPTY;
        }
        return n;
    }

    bool isTriangle(uint32_t prim) const { return prim < src_.triangleCount; }

    // Slots a binary node needs when placed as it is in a wide node.
    int slotsOf(const BinaryNode* b) const {
        if (!b->leaf()) return 1;
        bool tri = false, sph = false;
        for (uint32_t i = 0; i < b->count; ++i) (isTriangle(bvh_.order[b->first + i]) ? tri : sph) = true;
        return int(tri) + int(sph);
    }

    // SAH weight of a box: its surface area relative to the root's (probability that a
    // random ray hitting the root hits it).
    double weight(const Bounds3& b) const { return rootArea_ > 0.0f ? double(b.surfaceArea()) / rootArea_ : 1.0; }

    // Writes one wide node for binary node b (and recursively its subtree); returns its index.
    // `stack` receives S(node) from bvh_collapse.h.
    uint32_t emitNode(const BinaryNode* b, int depth, int& stack) {
        stats_.depth = std::max(stats_.depth, depth);
        const auto index = static_cast<uint32_t>(nodes_.size());
        nodes_.push_back(emptyNode());
        sah_ += weight(b->box) * src_.traversalCost;

        // Greedy: open the interior candidate with the largest surface area while it fits.
        std::vector<const BinaryNode*> cand;
        if (b->leaf()) cand.push_back(b);
        else {
            cand.push_back(b->child[0].get());
            cand.push_back(b->child[1].get());
        }
        for (;;) {
            int used = 0;
            for (auto* c : cand) used += slotsOf(c);
            int best = -1;
            float bestArea = -1.0f;
            for (size_t i = 0; i < cand.size(); ++i) {
                const BinaryNode* c = cand[i];
                if (c->leaf()) continue;
                int grown = used - 1 + slotsOf(c->child[0].get()) + slotsOf(c->child[1].get());
                float area = c->box.surfaceArea();
                if (grown <= PCL_BVH_WIDTH && area > bestArea) {
                    bestArea = area;
                    best = int(i);
                }
            }
            if (best < 0) break;
            const BinaryNode* open = cand[best];
            cand[best] = open->child[0].get();
            cand.push_back(open->child[1].get());
        }

        // Expand leaves into their primitive kinds, then write the slots.
        std::vector<Slot> slots;
        for (auto* c : cand) {
            if (!c->leaf()) {
                slots.push_back({c, false, false});
                continue;
            }
            bool tri = false, sph = false;
            for (uint32_t i = 0; i < c->count; ++i) (isTriangle(bvh_.order[c->first + i]) ? tri : sph) = true;
            if (tri) slots.push_back({c, true, false});
            if (sph) slots.push_back({c, true, true});
        }
        int childCount = static_cast<int>(slots.size());
        int deepest = 0;
        for (int i = 0; i < childCount; ++i) {
            const Slot& s = slots[i];
            Bounds3 box;
            uint32_t word;
            if (!s.leaf) {
                int childStack = 0;
                word = emitNode(s.node, depth + 1, childStack);
                deepest = std::max(deepest, childStack);
                box = s.node->box;
            } else {
                word = s.spheres ? emitSphereLeaf(s.node, box) : emitTriangleLeaf(s.node, box);
            }
            PclBvhNode& n = nodes_[index];  // re-fetch: emitNode may have grown the vector
            n.lox[i] = box.lo.x;
            n.loy[i] = box.lo.y;
            n.loz[i] = box.lo.z;
            n.hix[i] = box.hi.x;
            n.hiy[i] = box.hi.y;
            n.hiz[i] = box.hi.z;
            n.child[i] = word;
        }
        stack = std::max(childCount, childCount - 1 + deepest);
        return index;
    }

    static uint32_t leafWord(uint32_t first, uint32_t count, bool spheres) {
        return PCL_CHILD_LEAF | (spheres ? PCL_CHILD_SPHERES : 0u) | ((count - 1) << PCL_CHILD_COUNT_SHIFT) | first;
    }

    Bounds3 leafBox(const BinaryNode* b, bool spheres) const {
        Bounds3 box;
        for (uint32_t i = 0; i < b->count; ++i) {
            uint32_t p = bvh_.order[b->first + i];
            if (isTriangle(p) == spheres) continue;
            const Bounds3& pb = (*src_.boxes)[p];
            if (isFinite(pb.lo) && isFinite(pb.hi)) box.extend(pb);
        }
        return box;
    }

    uint32_t emitTriangleLeaf(const BinaryNode* b, Bounds3& box) {
        struct Tri {
            uint32_t prim;
            Vec3 v0, e1, e2, motion;
        };
        std::vector<Tri> tris;
        for (uint32_t i = 0; i < b->count; ++i) {
            uint32_t p = bvh_.order[b->first + i];
            if (!isTriangle(p)) continue;
            Tri t;
            t.prim = p;
            src_.triangle(p, t.v0, t.e1, t.e2, t.motion);
            tris.push_back(t);
        }
        // A packet shares one motion vector: group lanes by identical motion.
        std::stable_sort(tris.begin(), tris.end(), [](const Tri& a, const Tri& c) {
            if (a.motion.x != c.motion.x) return a.motion.x < c.motion.x;
            if (a.motion.y != c.motion.y) return a.motion.y < c.motion.y;
            return a.motion.z < c.motion.z;
        });
        const auto first = static_cast<uint32_t>(packets_.size());
        for (size_t i = 0; i < tris.size();) {
            PclTriPacket pk{};
            for (int l = 0; l < 4; ++l) pk.prim[l] = PCL_NO_HIT;  // empty lanes: zero edges, never hit
            Vec3 m = tris[i].motion;
            pk.mx = m.x;
            pk.my = m.y;
            pk.mz = m.z;
            for (int lane = 0; lane < 4 && i < tris.size() && tris[i].motion == m; ++lane, ++i) {
                const Tri& t = tris[i];
                pk.v0x[lane] = t.v0.x;
                pk.v0y[lane] = t.v0.y;
                pk.v0z[lane] = t.v0.z;
                pk.e1x[lane] = t.e1.x;
                pk.e1y[lane] = t.e1.y;
                pk.e1z[lane] = t.e1.z;
                pk.e2x[lane] = t.e2.x;
                pk.e2y[lane] = t.e2.y;
                pk.e2z[lane] = t.e2.z;
                pk.prim[lane] = t.prim;
            }
            packets_.push_back(pk);
        }
        const auto count = static_cast<uint32_t>(packets_.size()) - first;
        box = leafBox(b, false);
        stats_.leaves++;
        stats_.triangles += tris.size();
        sah_ += weight(box) * count;
        return leafWord(first, count, false);
    }

    uint32_t emitSphereLeaf(const BinaryNode* b, Bounds3& box) {
        const auto first = static_cast<uint32_t>(spheres_.size());
        for (uint32_t i = 0; i < b->count; ++i) {
            uint32_t p = bvh_.order[b->first + i];
            if (!isTriangle(p)) spheres_.push_back(src_.sphere(p));
        }
        const auto count = static_cast<uint32_t>(spheres_.size()) - first;
        box = leafBox(b, true);
        stats_.leaves++;
        sah_ += weight(box) * count;
        return leafWord(first, count, true);
    }

    const BinaryBvh& bvh_;
    const CollapseSource& src_;
    std::vector<PclBvhNode>& nodes_;
    std::vector<PclTriPacket>& packets_;
    std::vector<PclSphere>& spheres_;
    BvhStats& stats_;
    float rootArea_ = 0.0f;
    double sah_ = 0.0;
};

}  // namespace

void collapseBvh(const BinaryBvh& bvh, const CollapseSource& source, std::vector<PclBvhNode>& nodes,
                 std::vector<PclTriPacket>& packets, std::vector<PclSphere>& spheres, BvhStats& stats) {
    Collapser c(bvh, source, nodes, packets, spheres, stats);
    c.run();
    stats.nodes = nodes.size();
    stats.packets = packets.size();
    stats.spheres = spheres.size();
}

}  // namespace pcl
