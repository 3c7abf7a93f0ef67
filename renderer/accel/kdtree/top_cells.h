// The top of a kd-tree, cut at a depth: the subtrees there (and the leaves above it) that hold
// primitives, each with the box of what it holds. A ray tests eight of these boxes at once
// (meetsBoxes), as a BVH node tests its children, and enters only the subtrees whose boxes it
// meets, with its range clipped to each box. A kd-tree's cells tile space, and a ray that crosses
// the tree's box but misses every primitive otherwise walks through empty cells node by node (on
// the bunny's incoherent rays, 11 node steps and 2.3 empty leaves for each such ray, 3.5 times
// Embree's time); the boxes drop most of those rays at once, and shorten the range, and so the
// steps, of the others.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "accel/kdtree/leaf_data.h"

namespace caustic {

struct KdTopCells {
    /// The deepest cut: at most 2^6 = 64 cells, eight tests of eight boxes.
    static constexpr int kMaxDepth = 6;
    static constexpr uint32_t kMaxCells = 1u << kMaxDepth;

    /// The cells in the order a ray of one octant of directions visits them, front to back: the
    /// order of the traversal, which enters a node's child below its plane first where the
    /// direction's component on the plane's axis is positive. Cells tile space, so a ray meets
    /// them one after another in this order, and their boxes lie in them: the ranges of the
    /// boxes it meets come in this order too.
    struct Octant {
        uint32_t count = 0;            ///< Cells (with primitives).
        uint32_t stride = 0;           ///< count rounded up to kd_leaf::kLanes.
        std::vector<uint32_t> roots;   ///< The node where each cell's subtree starts.
        std::vector<uint32_t> bounds;  ///< Their boxes, as meetsBoxes reads them (float bits).
    };
    /// Indexed by directionSignBits.
    std::array<Octant, 8> octants;

    size_t memoryBytes() const {
        size_t bytes = 0;
        for (const Octant& o : octants)
            bytes += (o.roots.capacity() + o.bounds.capacity()) * sizeof(uint32_t);
        return bytes;
    }
};

}  // namespace caustic
