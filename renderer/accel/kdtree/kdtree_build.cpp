// The SAH build. Large nodes choose their split from bins of primitive bounds, small ones among
// every primitive boundary (split.h): O(N log N) in all. Nodes of kParallelLimit references or more
// are split by OpenMP tasks; every smaller subtree is built by one thread, depth first, straight
// into flat node and primitive arrays, with its references on one stack: a node's references lie at
// the top, its children's are pushed above them. No allocation per node, and the same tree as a
// recursion over per-node vectors.
#include <omp.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <memory>

#include "accel/kdtree/clip.h"
#include "accel/kdtree/kdtree.h"
#include "accel/kdtree/split.h"
#include "core/check.h"

namespace caustic {
namespace {

constexpr size_t kParallelLimit = 4096;

using Node = KdTreeAccel::Node;

Bounds3 childBox(const Bounds3& box, int axis, float pos, bool above) {
    Bounds3 b = box;
    (above ? b.lo : b.hi)[axis] = pos;
    return b;
}

// A primitive's box cut at +-FLT_MAX: the part beyond (a sphere of radius 3e38 at 3e38) has no
// float coordinates for a ray to reach, and every box of the tree then stays finite.
Bounds3 finiteBox(const Bounds3& b) {
    const Vec3 m(std::numeric_limits<float>::max());
    return Bounds3{glm::clamp(b.lo, -m, m), glm::clamp(b.hi, -m, m)};
}

// A subtree built by one thread: nodes depth first, above-child indices and leaf data offsets
// relative to its own arrays.
struct Subtree {
    std::vector<Node> nodes;
    std::vector<uint32_t> leafData;
    KdTreeStats stats;
};

// The top of the tree, split in parallel; each branch ends in a subtree.
struct TopNode {
    int axis = 0;
    float split = 0.0f;
    double areaRatio = 0.0;  // its box's area over the root's, for the SAH cost in the stats
    std::unique_ptr<TopNode> below, above;
    std::unique_ptr<Subtree> subtree;  // set: the node is this subtree's root
};

}  // namespace

class KdTreeBuilder {
public:
    KdTreeBuilder(KdTreeAccel& tree, const KdTreeOptions& options)
        : tree_(tree), geometry_(tree.geometry_), options_(options) {}

    void build() {
        uint32_t n = geometry_.size();
        std::vector<KdRef> refs(n);
        Bounds3 box;
        uint64_t weights = 0;
        for (uint32_t p = 0; p < n; ++p) {
            const uint32_t weight =
                geometry_.kind(p) == PrimKind::Triangle ? 1u : options_.leafBlock;
            refs[p] = KdRef{finiteBox(fuzzyBounds(geometry_, p)), p, weight};
            box.extend(refs[p].b);
            weights += weight;
        }
        // Sums of weights are 32-bit; so are the primitive indices, whose top bit the leaves
        // use (kd_leaf::kOtherKind). A node's references are a subset of the root's.
        CAUSTIC_CHECK_LT(weights, uint64_t(1) << 32);
        CAUSTIC_CHECK_LT(n, kd_leaf::kOtherKind);
        tree_.bounds_ = box;
        rootArea_ = surfaceAreaD(box);
        int maxDepth = options_.maxDepth > 0
                           ? options_.maxDepth
                           : int(std::lround(6 + 1.3 * std::log2(std::max<uint32_t>(n, 1))));
        maxDepth = std::min(maxDepth, KdTreeAccel::kMaxDepth);

        TopNode root;
#pragma omp parallel
#pragma omp single nowait
        buildTop(root, std::move(refs), box, maxDepth, 0, 0);
        size_t nodes = 0, words = kd_leaf::kPadWords;
        countSizes(root, nodes, words);
        tree_.nodes_.reserve(nodes);
        tree_.leafData_.reserve(words);
        flatten(root);
        tree_.leafData_.resize(tree_.leafData_.size() + kd_leaf::kPadWords);
    }

private:
    // The plane to split a node at, by the SAH; axis -1 for a leaf. Stops when splitting does not
    // pay (pbrt-v3's rule, allowing a few bad refinements since a worse split can enable better
    // ones below).
    KdSplit chooseSplit(std::span<const KdRef> refs, const Bounds3& box, int depthLeft,
                        int& badRefines) const {
        const size_t n = refs.size();
        if (n <= 1 || depthLeft == 0 || !(surfaceAreaD(box) > 0.0)) return {};
        KdSplit split = n > kExactSplitLimit ? findBinnedSplit(refs, box, options_)
                                             : findExactSplit(refs, box, options_);
        if (split.cost > split.leafCost) ++badRefines;
        if (split.axis < 0 || (split.cost > 4.0f * split.leafCost && n < 16) || badRefines == 3)
            return {};
        return split;
    }

    // Appends to `below` and `above` the references of each side of the plane: those overlapping
    // it, clipped to that side's box (a straddling primitive is clipped once for both). Neither
    // may reallocate while it runs if `refs` lies in it.
    void partition(std::span<const KdRef> refs, const Bounds3& box, int axis, float pos,
                   std::vector<KdRef>& below, std::vector<KdRef>& above) const {
        for (const KdRef& r : refs) {
            const float lo = component(r.b.lo, axis), hi = component(r.b.hi, axis);
            if (lo == pos && hi == pos) {
                // Lying in the plane: both sides, so rays in or through the plane find it.
                below.push_back(r);
                above.push_back(r);
            } else if (hi <= pos) {
                below.push_back(r);
            } else if (lo >= pos) {
                above.push_back(r);
            } else {
                Bounds3 b, a;
                if (options_.clipPrimitives) {
                    clipPrimitiveToChildren(geometry_, r.prim, box, axis, pos, b, a);
                } else {
                    b = childBox(box, axis, pos, false);
                    a = childBox(box, axis, pos, true);
                }
                b = Bounds3{glm::max(b.lo, r.b.lo), glm::min(b.hi, r.b.hi)};
                a = Bounds3{glm::max(a.lo, r.b.lo), glm::min(a.hi, r.b.hi)};
                if (!b.empty()) below.push_back(KdRef{b, r.prim, r.weight});
                if (!a.empty()) above.push_back(KdRef{a, r.prim, r.weight});
            }
        }
    }

    // One thread's depth-first build of a subtree, its references on `stack_`.
    class SerialBuild {
    public:
        SerialBuild(const KdTreeBuilder& builder, Subtree& out, std::vector<KdRef> refs)
            : b_(builder), out_(out), stack_(std::move(refs)) {}

        void node(size_t begin, size_t end, const Bounds3& box, int depthLeft, int badRefines,
                  uint32_t depth) {
            const size_t n = end - begin;
            auto index = uint32_t(out_.nodes.size());
            out_.nodes.emplace_back();
            out_.stats.maxDepth = std::max(out_.stats.maxDepth, depth);
            KdSplit split =
                b_.chooseSplit(std::span(stack_).subspan(begin, n), box, depthLeft, badRefines);
            if (split.axis < 0) return leaf(index, begin, end, box);

            // Both children's references at the top of the stack, below then above. The stack is
            // grown first, so that the pushes never move the parent's references.
            const size_t top = stack_.size();
            if (stack_.capacity() < top + 2 * n)
                stack_.reserve(std::max(2 * stack_.capacity(), top + 2 * n));
            const std::span<const KdRef> refs(stack_.data() + begin, n);
            above_.clear();
            b_.partition(refs, box, split.axis, split.pos, stack_, above_);
            const size_t mid = stack_.size();
            stack_.insert(stack_.end(), above_.begin(), above_.end());
            const size_t last = stack_.size();
            // A split that moved nothing is a loop: stop.
            if (mid - top == n && last - mid == n) {
                stack_.resize(top);
                return leaf(index, begin, end, box);
            }
            ++out_.stats.interiorNodes;
            out_.stats.sahCost += b_.areaRatio(box);
            node(top, mid, childBox(box, split.axis, split.pos, false), depthLeft - 1, badRefines,
                 depth + 1);
            stack_.resize(last);
            auto above = uint32_t(out_.nodes.size());
            CAUSTIC_CHECK_LT(above, 1u << 30);
            out_.nodes[index].split = split.pos;
            out_.nodes[index].bits = uint32_t(split.axis) | (above << 2);
            node(mid, last, childBox(box, split.axis, split.pos, true), depthLeft - 1, badRefines,
                 depth + 1);
            stack_.resize(top);
        }

        void leaf(uint32_t index, size_t begin, size_t end, const Bounds3& box) {
            auto count = uint32_t(end - begin);
            CAUSTIC_CHECK_LT(count, 1u << 30);
            Node& leaf = out_.nodes[index];
            leaf.bits = 3u | (count << 2);
            leaf.leafOffset = uint32_t(out_.leafData.size());
            b_.appendLeafData(std::span(stack_).subspan(begin, count), out_.leafData);
            KdTreeStats& stats = out_.stats;
            ++stats.leaves;
            if (count == 0) ++stats.emptyLeaves;
            stats.references += count;
            stats.sahCost +=
                leafCost(b_.options_, totalWeight(std::span(stack_).subspan(begin, count))) *
                b_.areaRatio(box) / b_.options_.traversalCost;
        }

    private:
        const KdTreeBuilder& b_;
        Subtree& out_;
        std::vector<KdRef> stack_;
        std::vector<KdRef> above_;  // a partition's above side, before it joins the stack
    };

    // A leaf's primitives and their triangles' vertices, in kd_leaf's layout (leaf_data.h), in
    // blocks of spatial clusters with their boxes. Orders `refs` (the leaf's part of the
    // reference stack, which the leaf is the last to read) into those blocks in place.
    void appendLeafData(std::span<KdRef> refs, std::vector<uint32_t>& data) const {
        orderIntoBlocks(refs);
        const auto n = uint32_t(refs.size());
        const size_t base = data.size();
        data.resize(base + kd_leaf::words(n));
        uint32_t* leaf = data.data() + base;
        for (uint32_t i = 0; i < n; ++i) {
            const uint32_t prim = refs[i].prim;
            const bool triangle = geometry_.kind(prim) == PrimKind::Triangle;
            leaf[kd_leaf::primitives(n) + i] = triangle ? prim : prim | kd_leaf::kOtherKind;
            if (!triangle) continue;
            Vec3 p[3];
            geometry_.triangleVertices(geometry_.localIndex(prim), p[0], p[1], p[2]);
            for (int v = 0; v < 3; ++v)
                for (int a = 0; a < 3; ++a)
                    leaf[kd_leaf::coordinate(n, v, a) + i] =
                        std::bit_cast<uint32_t>(component(p[v], a));
        }
        // Each block's box: its references' boxes, already clipped to the leaf's cell.
        for (uint32_t b = 0; b < kd_leaf::blocks(n); ++b) {
            Bounds3 box;
            for (uint32_t i = b * kd_leaf::kLanes; i < std::min(n, (b + 1) * kd_leaf::kLanes); ++i)
                box.extend(refs[i].b);
            storeBoxInRows(leaf + kd_leaf::blockBound(n, 0, 0), kd_leaf::blocks(n), b, box);
        }
    }

    // Orders references so that each run of kd_leaf::kLanes is a cluster: halves at the median
    // of their boxes' centres on the centres' widest axis, each half a whole number of blocks,
    // until a part is one block. Ties go by primitive index, so the order is the same on every
    // run.
    static void orderIntoBlocks(std::span<KdRef> refs) {
        if (refs.size() <= size_t(kd_leaf::kLanes)) return;
        Bounds3 centres;
        for (const KdRef& r : refs) centres.extend(r.b.center());
        const Vec3 d = centres.diagonal();
        const int axis = d.x >= d.y && d.x >= d.z ? 0 : (d.y >= d.z ? 1 : 2);
        const size_t blocks = (refs.size() + kd_leaf::kLanes - 1) / kd_leaf::kLanes;
        const size_t mid = size_t(kd_leaf::kLanes) * ((blocks + 1) / 2);
        std::nth_element(refs.begin(), refs.begin() + std::ptrdiff_t(mid), refs.end(),
                         [axis](const KdRef& a, const KdRef& b) {
                             const float ca = component(a.b.lo, axis) + component(a.b.hi, axis);
                             const float cb = component(b.b.lo, axis) + component(b.b.hi, axis);
                             return ca < cb || (ca == cb && a.prim < b.prim);
                         });
        orderIntoBlocks(refs.first(mid));
        orderIntoBlocks(refs.subspan(mid));
    }

    double areaRatio(const Bounds3& box) const {
        return rootArea_ > 0.0 ? surfaceAreaD(box) / rootArea_ : 0.0;
    }

    void buildSubtree(TopNode& node, std::vector<KdRef> refs, const Bounds3& box, int depthLeft,
                      int badRefines, uint32_t depth) const {
        node.subtree = std::make_unique<Subtree>();
        const size_t n = refs.size();
        SerialBuild(*this, *node.subtree, std::move(refs))
            .node(0, n, box, depthLeft, badRefines, depth);
    }

    void buildTop(TopNode& node, std::vector<KdRef> refs, const Bounds3& box, int depthLeft,
                  int badRefines, uint32_t depth) {
        const size_t n = refs.size();
        if (n < kParallelLimit)
            return buildSubtree(node, std::move(refs), box, depthLeft, badRefines, depth);
        int bad = badRefines;
        KdSplit split = chooseSplit(refs, box, depthLeft, bad);
        std::vector<KdRef> below, above;
        if (split.axis >= 0) {
            below.reserve(n);
            above.reserve(n);
            partition(refs, box, split.axis, split.pos, below, above);
        }
        // A leaf, or a split that moved nothing: the serial build decides the same and ends here.
        if (split.axis < 0 || (below.size() == n && above.size() == n))
            return buildSubtree(node, std::move(refs), box, depthLeft, badRefines, depth);
        refs.clear();
        refs.shrink_to_fit();
        node.axis = split.axis;
        node.split = split.pos;
        node.areaRatio = areaRatio(box);
        node.below = std::make_unique<TopNode>();
        node.above = std::make_unique<TopNode>();
        Bounds3 belowBox = childBox(box, split.axis, split.pos, false);
        Bounds3 aboveBox = childBox(box, split.axis, split.pos, true);
#pragma omp task default(shared) firstprivate(belowBox, depthLeft, bad, depth)
        buildTop(*node.below, std::move(below), belowBox, depthLeft - 1, bad, depth + 1);
        buildTop(*node.above, std::move(above), aboveBox, depthLeft - 1, bad, depth + 1);
#pragma omp taskwait
    }

    // The nodes and leaf data words of the tree below `node`, added to `nodes` and `words`.
    static void countSizes(const TopNode& node, size_t& nodes, size_t& words) {
        if (node.subtree) {
            nodes += node.subtree->nodes.size();
            words += node.subtree->leafData.size();
            return;
        }
        ++nodes;
        countSizes(*node.below, nodes, words);
        countSizes(*node.above, nodes, words);
    }

    // Writes the tree depth first (a node's below child follows it, its above child's index is
    // stored in the node), copying each subtree's arrays with their indices moved to where they
    // land. Frees the top's nodes and the subtrees on the way.
    void flatten(TopNode& node) {
        std::vector<Node>& nodes = tree_.nodes_;
        KdTreeStats& stats = tree_.stats_;
        if (node.subtree) {
            const Subtree& s = *node.subtree;
            std::vector<uint32_t>& leafData = tree_.leafData_;
            const auto base = uint32_t(nodes.size()), dataBase = uint32_t(leafData.size());
            CAUSTIC_CHECK_LT(uint64_t(base) + s.nodes.size(), uint64_t(1) << 30);
            CAUSTIC_CHECK_LT(uint64_t(dataBase) + s.leafData.size(), uint64_t(1) << 32);
            for (Node n : s.nodes) {
                if (!n.isLeaf())
                    n.bits += base << 2;
                else
                    n.leafOffset += dataBase;
                nodes.push_back(n);
            }
            leafData.insert(leafData.end(), s.leafData.begin(), s.leafData.end());
            stats.interiorNodes += s.stats.interiorNodes;
            stats.leaves += s.stats.leaves;
            stats.emptyLeaves += s.stats.emptyLeaves;
            stats.maxDepth = std::max(stats.maxDepth, s.stats.maxDepth);
            stats.references += s.stats.references;
            stats.sahCost += s.stats.sahCost;
            node.subtree.reset();
            return;
        }
        // The top's nodes are interior: a leaf among them is a subtree of one node.
        auto index = uint32_t(nodes.size());
        nodes.emplace_back();
        ++stats.interiorNodes;
        stats.sahCost += node.areaRatio;
        flatten(*node.below);
        node.below.reset();
        auto above = uint32_t(nodes.size());
        nodes[index].split = node.split;
        nodes[index].bits = uint32_t(node.axis) | (above << 2);
        flatten(*node.above);
        node.above.reset();
    }

    KdTreeAccel& tree_;
    const Geometry& geometry_;
    KdTreeOptions options_;
    double rootArea_ = 0.0;
};

KdTreeAccel::KdTreeAccel(const Geometry& geometry, const KdTreeOptions& options)
    : geometry_(geometry) {
    static_assert(sizeof(Node) == 8);
    CAUSTIC_CHECK(std::has_single_bit(options.leafBlock));
    CAUSTIC_CHECK(options.topDepth >= 0 && options.topDepth <= KdTopCells::kMaxDepth);
    KdTreeBuilder(*this, options).build();
    buildTopCells(options.topDepth);
}

size_t KdTreeAccel::memoryBytes() const {
    return nodes_.capacity() * sizeof(Node) + leafData_.capacity() * sizeof(uint32_t) +
           top_.memoryBytes();
}

}  // namespace caustic
