// The surface area heuristic's choice of a split plane for a node of the kd-tree's build.
#pragma once

#include <cstdint>
#include <limits>
#include <span>

#include "accel/kdtree/kdtree.h"
#include "core/bounds.h"

namespace caustic {

/// A primitive's reference in a node of the build: its bounds clipped to the node's box, and its
/// weight in the SAH's counts: 1 for a triangle, which a leaf tests leafBlock at a time, and
/// leafBlock for any other primitive (a sphere or a quad), which it tests by itself
/// (KdTreeOptions). The searches below count weights where they would count references.
struct KdRef {
    Bounds3 b;
    uint32_t prim;
    uint32_t weight = 1;
};

/// The weights of `refs`, summed.
uint32_t totalWeight(std::span<const KdRef> refs);

/// The SAH cost of a leaf of references weighing `weight` in all, relative to traversalCost's
/// units as KdSplit::cost (its area ratio aside).
inline double leafCost(const KdTreeOptions& options, uint32_t weight) {
    return options.intersectCost * double(options.leafTests(weight));
}

struct KdSplit {
    int axis = -1;  ///< -1: no plane inside the box
    float pos = 0.0f;
    double cost = std::numeric_limits<double>::infinity();
    double leafCost = 0.0;  ///< The node's cost as a leaf, to compare with `cost`.
};

/// Nodes of more references than this choose among bin edges, smaller ones among every boundary.
inline constexpr size_t kExactSplitLimit = 64;

/// Area of a box, in double: float coordinates of a box can lie up to 2 FLT_MAX apart (a sphere of
/// radius 3e38), and the area overflows float from 1.8e19 on.
double surfaceAreaD(const Bounds3& b);

/// The cheapest split of `box` by the SAH among 32 bin edges per axis (Popov et al. 2006,
/// "Experiences with Streaming Construction of SAH KD-Trees"): O(n).
KdSplit findBinnedSplit(std::span<const KdRef> refs, const Bounds3& box,
                        const KdTreeOptions& options);
/// The cheapest split among every reference's boundaries (pbrt-v3 4.4.2), for at most
/// kExactSplitLimit references.
KdSplit findExactSplit(std::span<const KdRef> refs, const Bounds3& box,
                       const KdTreeOptions& options);

}  // namespace caustic
