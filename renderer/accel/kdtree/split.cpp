#include "accel/kdtree/split.h"

#include <algorithm>
#include <bit>
#include <cstdint>

#include "core/check.h"

namespace caustic {
namespace {

constexpr int kBins = 32;

glm::dvec3 diagonalD(const Bounds3& b) {
    return glm::dvec3(b.hi) - glm::dvec3(b.lo);
}

// The bin of a position scaled to [0, kBins), clamped in double before the conversion to int,
// which is undefined for NaN and out-of-range values.
int binOf(double scaled) {
    return scaled >= 0.0 ? int(std::min(scaled, double(kBins - 1))) : 0;
}

// The SAH cost of splitting `box` on one axis, with what it needs computed once per node and
// axis rather than once per candidate plane (a node of n references has 2n of them).
class SplitCost {
public:
    SplitCost(const KdTreeOptions& options, const Bounds3& box, int axis)
        : traversal_(options.traversalCost),
          intersect_(options.intersectCost),
          emptyBonus_(options.emptyBonus),
          blockShift_(uint32_t(std::countr_zero(options.leafBlock))),
          lo_(box.lo[axis]),
          hi_(box.hi[axis]) {
        const glm::dvec3 d = diagonalD(box);
        const int o1 = (axis + 1) % 3, o2 = (axis + 2) % 3;
        const double invArea = 1.0 / surfaceAreaD(box);
        cap_ = 2.0 * d[o1] * d[o2] * invArea;
        ring_ = 2.0 * (d[o1] + d[o2]) * invArea;
    }
    // Without branches, so that a loop over candidates vectorizes: leafTests by a shift.
    double operator()(float pos, uint32_t nBelow, uint32_t nAbove) const {
        const double below = cap_ + (double(pos) - lo_) * ring_;
        const double above = cap_ + (hi_ - double(pos)) * ring_;
        const double bonus = double((nBelow == 0) | (nAbove == 0)) * emptyBonus_;
        const uint32_t round = (1u << blockShift_) - 1u;
        const double testsBelow = double((nBelow + round) >> blockShift_);
        const double testsAbove = double((nAbove + round) >> blockShift_);
        return traversal_ + intersect_ * (1.0 - bonus) * (below * testsBelow + above * testsAbove);
    }

private:
    double traversal_, intersect_, emptyBonus_;
    uint32_t blockShift_;
    double lo_, hi_, cap_ = 0, ring_ = 0;
};

}  // namespace

uint32_t totalWeight(std::span<const KdRef> refs) {
    uint32_t sum = 0;
    for (const KdRef& r : refs) sum += r.weight;
    return sum;
}

double surfaceAreaD(const Bounds3& b) {
    if (b.empty()) return 0.0;
    glm::dvec3 d = diagonalD(b);
    return 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
}

// Counts each axis' starts and ends per bin in one pass over the references (each is read once,
// not once per axis), then sweeps every axis' bin edges.
KdSplit findBinnedSplit(std::span<const KdRef> refs, const Bounds3& box,
                        const KdTreeOptions& options) {
    double lo[3], extent[3], scale[3];
    for (int axis = 0; axis < 3; ++axis) {
        lo[axis] = box.lo[axis];
        extent[axis] = double(box.hi[axis]) - lo[axis];
        scale[axis] = extent[axis] > 0.0 ? kBins / extent[axis] : 0.0;
    }
    uint32_t starts[3][kBins] = {}, ends[3][kBins] = {};  // weights
    uint32_t total = 0;
    for (const KdRef& r : refs) {
        total += r.weight;
        for (int axis = 0; axis < 3; ++axis) {
            starts[axis][binOf((component(r.b.lo, axis) - lo[axis]) * scale[axis])] += r.weight;
            ends[axis][binOf((component(r.b.hi, axis) - lo[axis]) * scale[axis])] += r.weight;
        }
    }
    constexpr double kInfinityD = std::numeric_limits<double>::infinity();
    KdSplit best;
    for (int axis = 0; axis < 3; ++axis) {
        if (!(extent[axis] > 0.0)) continue;
        const SplitCost cost(options, box, axis);
        // The counts at each edge, then every edge's cost in a vectorized loop (+infinity where
        // a box a few floats wide has bin edges that round onto its faces), then the cheapest.
        uint32_t nBelow[kBins], nAbove[kBins];
        nBelow[0] = 0;
        nAbove[0] = total;
        for (int i = 1; i < kBins; ++i) {
            nBelow[i] = nBelow[i - 1] + starts[axis][i - 1];
            nAbove[i] = nAbove[i - 1] - ends[axis][i - 1];
        }
        const float boxLo = box.lo[axis], boxHi = box.hi[axis];
        alignas(64) float pos[kBins];
        alignas(64) double edgeCost[kBins];
        // From edge 0, the box's own face (never inside, so never chosen): whole vectors.
        for (int i = 0; i < kBins; ++i) {
            pos[i] = float(lo[axis] + extent[axis] * i / kBins);
            const double c = cost(pos[i], nBelow[i], nAbove[i]);
            edgeCost[i] = ((pos[i] > boxLo) & (pos[i] < boxHi)) ? c : kInfinityD;
        }
        for (int i = 1; i < kBins; ++i)
            if (edgeCost[i] < best.cost) best = KdSplit{axis, pos[i], edgeCost[i]};
    }
    best.leafCost = leafCost(options, total);
    return best;
}

// The sweep of pbrt-v3 4.4.2 visits the 2n boundaries in sorted order, starts before ends at equal
// positions, and keeps the first of equal costs. Here each boundary's counts (weights, KdRef) come
// from comparisons with all the others instead: a start s is preceded by the starts and the ends
// strictly below it, an end e by the starts at or below it and the ends at or below it but itself.
// Boundaries of equal kind and position need no order among them: the sweep's cost never falls
// with a start of such a run (more weight below) and never rises with an end (less above), so the
// run's first start and last end are its cheapest, and these counts give every member of a run
// that one's counts and cost, at the same position. The sum of a boundary's predecessors' weights
// is its position in the sweep, up to the order within its run, and breaks ties between equal
// costs, so the split is the sweep's. That is 4n^2 comparisons per axis for at most 64
// references, made a boundary per vector lane, in place of two sorts and a merge whose branches
// mispredict on every other boundary.
KdSplit findExactSplit(std::span<const KdRef> refs, const Bounds3& box,
                       const KdTreeOptions& options) {
    const auto n = uint32_t(refs.size());
    CAUSTIC_CHECK_LE(n, kExactSplitLimit);
    const uint32_t total = totalWeight(refs);
    // Padded to whole vectors with +infinity, which no count includes, so the loops over lanes
    // run without a remainder.
    constexpr uint32_t kLanes = 16;
    const uint32_t padded = (n + kLanes - 1) / kLanes * kLanes;
    alignas(64) float starts[kExactSplitLimit], ends[kExactSplitLimit];
    alignas(64) uint32_t weights[kExactSplitLimit];
    // A boundary's cost and its position in the sweep (the weight of its predecessors).
    alignas(64) double startCost[kExactSplitLimit], endCost[kExactSplitLimit];
    alignas(64) uint32_t startOrder[kExactSplitLimit], endOrder[kExactSplitLimit];
    constexpr double kInfinityD = std::numeric_limits<double>::infinity();
    KdSplit best;
    for (int axis = 0; axis < 3; ++axis) {
        const float lo = box.lo[axis], hi = box.hi[axis];
        if (!(hi > lo)) continue;
        for (uint32_t i = 0; i < n; ++i) {
            starts[i] = component(refs[i].b.lo, axis);
            ends[i] = component(refs[i].b.hi, axis);
            weights[i] = refs[i].weight;
        }
        for (uint32_t i = n; i < padded; ++i) {
            starts[i] = ends[i] = kInfinity;
            weights[i] = 0;
        }
        const SplitCost cost(options, box, axis);
        // A block of 16 boundaries at a time: its four sums in registers, then their costs,
        // +infinity outside the box (never chosen; nor is the padding, +infinity). The end itself
        // has passed when the sweep evaluates it.
        for (uint32_t i0 = 0; i0 < padded; i0 += kLanes) {
            uint32_t sBeforeS[kLanes] = {}, eBeforeS[kLanes] = {}, sBeforeE[kLanes] = {},
                     eBeforeE[kLanes] = {};
            for (uint32_t j = 0; j < n; ++j) {
                const float sj = starts[j], ej = ends[j];
                const uint32_t wj = weights[j];
                for (uint32_t l = 0; l < kLanes; ++l) {
                    const float s = starts[i0 + l], e = ends[i0 + l];
                    // Selects, which compile to one masked add each (an add of 0 or wj takes
                    // a compare, a masked move and an add).
                    sBeforeS[l] = sj < s ? sBeforeS[l] + wj : sBeforeS[l];
                    eBeforeS[l] = ej < s ? eBeforeS[l] + wj : eBeforeS[l];
                    sBeforeE[l] = sj <= e ? sBeforeE[l] + wj : sBeforeE[l];
                    eBeforeE[l] = ej <= e ? eBeforeE[l] + wj : eBeforeE[l];
                }
            }
            for (uint32_t l = 0; l < kLanes; ++l) {
                const uint32_t i = i0 + l;
                const float s = starts[i], e = ends[i];
                const uint32_t endsBeforeEnd = eBeforeE[l] - weights[i];  // not itself
                const double sc = cost(s, sBeforeS[l], total - eBeforeS[l]);
                const double ec = cost(e, sBeforeE[l], total - eBeforeE[l]);
                startCost[i] = ((s > lo) & (s < hi)) ? sc : kInfinityD;
                endCost[i] = ((e > lo) & (e < hi)) ? ec : kInfinityD;
                startOrder[i] = sBeforeS[l] + eBeforeS[l];
                endOrder[i] = sBeforeE[l] + endsBeforeEnd;
            }
        }
        // The cheapest, the first in the sweep of equal ones.
        double axisCost = best.cost;
        float axisPos = 0.0f;
        uint32_t axisOrder = 0;
        bool found = false;
        auto consider = [&](double c, float pos, uint32_t order) {
            if (c < axisCost || (found && c == axisCost && order < axisOrder)) {
                axisCost = c;
                axisPos = pos;
                axisOrder = order;
                found = true;
            }
        };
        for (uint32_t i = 0; i < n; ++i) {
            consider(startCost[i], starts[i], startOrder[i]);
            consider(endCost[i], ends[i], endOrder[i]);
        }
        if (found) best = KdSplit{axis, axisPos, axisCost};
    }
    best.leafCost = leafCost(options, total);
    return best;
}

}  // namespace caustic
