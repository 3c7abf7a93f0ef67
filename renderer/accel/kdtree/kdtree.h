// Our own kd-tree for ray intersection over every primitive kind, built by the surface area
// heuristic (MacDonald & Booth 1990; Wald & Havran 2006, "On building fast kd-trees for ray
// tracing, and on doing that in O(N log N)"). Structure and traversal follow pbrt-v3's KdTreeAccel
// (section 4.4): 8-byte nodes in depth-first order, front-to-back traversal with an explicit stack.
// Leaves hold their triangles' vertices in spatial blocks of eight with their boxes, and test
// eight boxes, then eight triangles, at once (leaf_data.h). The subtrees at a small depth have
// boxes too, which a ray tests eight at once before it takes a step (top_cells.h).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "accel/accelerator.h"
#include "accel/kdtree/leaf_data.h"
#include "accel/kdtree/top_cells.h"

namespace caustic {

/// Costs and limits of the SAH build. Costs are relative: only their ratio matters. The defaults
/// are chosen with `bench_accel_rays --kdtree-variants` (bench/README.md): a leaf culls its blocks
/// of eight by their boxes, eight boxes at once, before it tests any triangle, so that a ray tests
/// about one block of a leaf it enters and a block costs a thirtieth of a node visit (0.06 and
/// 0.015 are slower on some rows). pbrt-v3's costs (1.5 a primitive, empty bonus 0.3) give the
/// bunny 18 times the nodes of a tree costed at 0.25 a block, built 3.4 times as slowly, and rays
/// 1.09 to 1.41 times as slow.
struct KdTreeOptions {
    float traversalCost = 1.0f;   ///< Visiting an interior node.
    float intersectCost = 0.03f;  ///< Testing one block of leafBlock primitives.
    /// The leaf test's width, a power of two: a leaf of n triangles costs ceil(n / leafBlock)
    /// tests, as Embree's SAH counts a node's primitives in blocks of its leaves' width
    /// (kernels/builders/heuristic_binning.h); any other primitive costs a test by itself.
    /// 1: every primitive costs one test (pbrt-v3).
    uint32_t leafBlock = kd_leaf::kLanes;
    float emptyBonus = 0.15f;  ///< Discount for splits that cut off empty space, in [0, 1).
    /// 0: 6 + 1.3 log2(N), at most kMaxDepth. pbrt-v3's 8 + 1.3 log2(N) makes trees 1.4 to 1.9
    /// times as large, 1.3 to 1.8 times as slow to build, for rays as fast within the machine's
    /// noise (`bench_accel_rays --kdtree-depths`: bunny, teapot, bunny-1m, primary and incoherent
    /// rays).
    int maxDepth = 0;
    bool clipPrimitives = true;  ///< Clip straddling primitives to child boxes ("perfect splits").
    /// The depth of the top cells (top_cells.h), at most KdTopCells::kMaxDepth; 0: the whole tree
    /// is one cell, with the box of every primitive.
    int topDepth = 6;

    /// The tests a leaf of n triangles costs.
    uint32_t leafTests(uint32_t n) const { return (n + leafBlock - 1) / leafBlock; }
};

/// What the build produced, for benchmarks and tests.
struct KdTreeStats {
    uint32_t interiorNodes = 0;
    uint32_t leaves = 0;
    uint32_t emptyLeaves = 0;
    uint32_t maxDepth = 0;
    uint64_t references = 0;  ///< Primitive references in leaves (a primitive may be in several).
    double sahCost = 0;       ///< Expected cost of a ray by the SAH, relative to traversalCost.
    uint32_t topCells = 0;    ///< Top cells with primitives (top_cells.h).
};

class KdTreeAccel final : public Accelerator {
public:
    static constexpr int kMaxDepth = 60;

    /// Builds the tree over `geometry` (which must outlive it), in O(N log N).
    explicit KdTreeAccel(const Geometry& geometry, const KdTreeOptions& options = {});

    std::optional<Hit> intersect(const Ray& ray, float tMax) const override;
    bool occluded(const Ray& ray, float tMax) const override;
    Bounds3 bounds() const override { return bounds_; }
    size_t memoryBytes() const override;
    const KdTreeStats& stats() const { return stats_; }

    struct Node;
    /// The tree as built, depth first, and its leaves' data (accel/kdtree/leaf_data.h): for tests
    /// that the build is deterministic.
    std::span<const Node> nodes() const { return nodes_; }
    std::span<const uint32_t> leafData() const { return leafData_; }
    const KdTopCells& topCells() const { return top_; }

    /// A node: 4 bytes of split position or leaf data offset, 4 bytes of flags and counts.
    struct Node {
        union {
            float split;          // interior: the split plane's coordinate
            uint32_t leafOffset;  // leaf: where its data starts in leafData_
        };
        uint32_t bits;  // low 2 bits: axis 0-2, or 3 for a leaf; high 30: above child or prim count

        bool isLeaf() const { return (bits & 3u) == 3u; }
        int axis() const { return int(bits & 3u); }
        uint32_t aboveChild() const { return bits >> 2; }
        uint32_t primCount() const { return bits >> 2; }
    };

private:
    template <bool AnyHit>
    bool traverse(const Ray& ray, float tMax, uint32_t& prim, PrimHit& hit) const;
    void buildTopCells(int depth);  // after the build: top_ from nodes_ and leafData_

    const Geometry& geometry_;
    Bounds3 bounds_;
    std::vector<Node> nodes_;
    std::vector<uint32_t> leafData_;  // the leaves' primitives and vertices, kd_leaf's layout
    KdTopCells top_;
    KdTreeStats stats_;

    friend class KdTreeBuilder;
};

}  // namespace caustic
