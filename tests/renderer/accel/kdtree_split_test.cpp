// The exact split search counts each boundary's predecessors by comparisons instead of sorting.
// It must choose what pbrt-v3's sweep over sorted events chooses (4.4.2): the same axis, plane and
// cost, ties included, with leaves costed per primitive as there or per block of primitives, and
// references weighing one or a whole block. The
// references' bounds here are drawn from a few values per axis, so that many boundaries coincide,
// starts with ends and with the box's faces.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "accel/kdtree/split.h"

namespace caustic {
namespace {

// pbrt-v3's sweep: events sorted by position, starts before ends at equal positions; the first of
// equal costs is kept. The cost is the one findExactSplit uses (split.cpp), written out again.
KdSplit sweepSortedEvents(const std::vector<KdRef>& refs, const Bounds3& box,
                          const KdTreeOptions& options) {
    KdSplit best;
    for (int axis = 0; axis < 3; ++axis) {
        if (!(box.hi[axis] > box.lo[axis])) continue;
        struct Event {
            float pos;
            bool isEnd;
            uint32_t weight;
        };
        std::vector<Event> events;
        for (const KdRef& r : refs) {
            events.push_back({r.b.lo[axis], false, r.weight});
            events.push_back({r.b.hi[axis], true, r.weight});
        }
        std::stable_sort(events.begin(), events.end(), [](const Event& a, const Event& b) {
            return a.pos < b.pos || (a.pos == b.pos && !a.isEnd && b.isEnd);
        });
        const glm::dvec3 d = glm::dvec3(box.hi) - glm::dvec3(box.lo);
        const int o1 = (axis + 1) % 3, o2 = (axis + 2) % 3;
        const double invArea = 1.0 / surfaceAreaD(box);
        const double cap = 2.0 * d[o1] * d[o2] * invArea, ring = 2.0 * (d[o1] + d[o2]) * invArea;
        uint32_t nBelow = 0, nAbove = totalWeight(refs);
        for (const Event& e : events) {
            if (e.isEnd) nAbove -= e.weight;
            if (e.pos > box.lo[axis] && e.pos < box.hi[axis]) {
                const double below = cap + (double(e.pos) - box.lo[axis]) * ring;
                const double above = cap + (double(box.hi[axis]) - e.pos) * ring;
                const double bonus = (nBelow == 0 || nAbove == 0) ? options.emptyBonus : 0.0;
                const double testsBelow = options.leafTests(nBelow);
                const double testsAbove = options.leafTests(nAbove);
                const double c =
                    options.traversalCost + options.intersectCost * (1.0 - bonus) *
                                                (below * testsBelow + above * testsAbove);
                if (c < best.cost) best = KdSplit{axis, e.pos, c};
            }
            if (!e.isEnd) nBelow += e.weight;
        }
    }
    return best;
}

TEST(KdTreeSplit, ExactSearchChoosesWhatTheSortedSweepChooses) {
    std::mt19937 rng(17);
    const Bounds3 box{Vec3(0.0f), Vec3(4.0f, 2.0f, 1.0f)};
    int withSplit = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        // 1 to 64 references, coordinates on a grid of `steps` values per axis reaching past the
        // box.
        const auto n = size_t(1 + rng() % kExactSplitLimit);
        const int steps = 2 + int(rng() % 8);
        auto coordinate = [&](int axis) {
            const float extent = box.hi[axis] - box.lo[axis];
            return box.lo[axis] - 0.25f * extent +
                   1.5f * extent * float(rng() % unsigned(steps)) / float(steps);
        };
        // Blocks of leaf tests make runs of equal costs (a start or an end that does not change
        // a side's block count): the first of them must still win. A quarter of the references
        // weigh a whole block, as spheres and quads do in the build.
        KdTreeOptions options;
        options.emptyBonus = (trial % 3 == 0) ? 0.0f : 0.3f;
        options.leafBlock = 1u << (trial % 4);
        options.intersectCost = (trial % 2 == 0) ? 1.5f : 0.25f;
        std::vector<KdRef> refs;
        for (uint32_t i = 0; i < n; ++i) {
            KdRef r{{}, i, rng() % 4 == 0 ? options.leafBlock : 1u};
            for (int axis = 0; axis < 3; ++axis) {
                const float a = coordinate(axis), b = coordinate(axis);
                r.b.lo[axis] = std::min(a, b);
                r.b.hi[axis] = std::max(a, b);
            }
            refs.push_back(r);
        }
        const KdSplit want = sweepSortedEvents(refs, box, options);
        const KdSplit got = findExactSplit(refs, box, options);
        ASSERT_EQ(got.axis, want.axis) << "trial " << trial << ", " << n << " references";
        ASSERT_EQ(got.pos, want.pos) << "trial " << trial;
        if (want.axis >= 0) {
            ASSERT_EQ(got.cost, want.cost) << "trial " << trial;
            ++withSplit;
        }
    }
    EXPECT_GT(withSplit, 3000);
}

}  // namespace
}  // namespace caustic
