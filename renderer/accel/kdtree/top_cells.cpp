// The top cells of a built tree (top_cells.h). Their boxes come from the leaves' block boxes,
// which are the boxes of the leaves' references clipped to their cells: a cell's box holds every
// part of a primitive that its subtree holds, so a ray that misses the box misses all of them.
#include <algorithm>
#include <bit>

#include "accel/kdtree/kdtree.h"

namespace caustic {
namespace {

using Node = KdTreeAccel::Node;

struct Cell {
    uint32_t root;
    Bounds3 box;
};

Bounds3 subtreeBox(std::span<const Node> nodes, const uint32_t* leafData, uint32_t index) {
    const Node& node = nodes[index];
    Bounds3 box;
    if (!node.isLeaf()) {
        box.extend(subtreeBox(nodes, leafData, index + 1));
        box.extend(subtreeBox(nodes, leafData, node.aboveChild()));
        return box;
    }
    const uint32_t n = node.primCount();
    for (uint32_t b = 0; b < kd_leaf::blocks(n); ++b)
        box.extend(loadBoxInRows(leafData + node.leafOffset + kd_leaf::blockBound(n, 0, 0),
                                 kd_leaf::blocks(n), b));
    return box;
}

// The roots of the cells under `index`, `depth` levels down (or leaves above), in the order of
// the traversal for a direction of sign bits `negative`.
void cellRoots(std::span<const Node> nodes, uint32_t index, int depth, uint32_t negative,
               std::vector<uint32_t>& roots) {
    const Node& node = nodes[index];
    if (depth == 0 || node.isLeaf()) {
        roots.push_back(index);
        return;
    }
    uint32_t nearChild = index + 1, farChild = node.aboveChild();
    if ((negative >> node.axis()) & 1u) std::swap(nearChild, farChild);
    cellRoots(nodes, nearChild, depth - 1, negative, roots);
    cellRoots(nodes, farChild, depth - 1, negative, roots);
}

}  // namespace

void KdTreeAccel::buildTopCells(int depth) {
    top_ = KdTopCells{};
    if (nodes_.empty()) return;
    std::vector<uint32_t> roots;
    cellRoots(nodes_, 0, depth, 0, roots);
    // Every cell's box once, by root; cells without primitives are dropped.
    std::vector<Cell> cells;
    for (uint32_t root : roots) {
        const Bounds3 box = subtreeBox(nodes_, leafData_.data(), root);
        if (!box.empty()) cells.push_back(Cell{root, box});
    }
    std::ranges::sort(cells, {}, &Cell::root);

    for (uint32_t negative = 0; negative < 8; ++negative) {
        KdTopCells::Octant& octant = top_.octants[negative];
        octant.count = uint32_t(cells.size());
        octant.stride = (octant.count + kd_leaf::kLanes - 1) / kd_leaf::kLanes * kd_leaf::kLanes;
        octant.bounds.assign(6 * octant.stride, 0u);
        roots.clear();
        cellRoots(nodes_, 0, depth, negative, roots);
        for (uint32_t root : roots) {
            const auto cell = std::ranges::lower_bound(cells, root, {}, &Cell::root);
            if (cell == cells.end() || cell->root != root) continue;
            storeBoxInRows(octant.bounds.data(), octant.stride, uint32_t(octant.roots.size()),
                           cell->box);
            octant.roots.push_back(root);
        }
    }
    stats_.topCells = uint32_t(cells.size());
}

}  // namespace caustic
