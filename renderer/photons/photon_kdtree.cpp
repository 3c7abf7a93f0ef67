#include "photons/photon_kdtree.h"

#include <algorithm>

#include "core/bounds.h"
#include "core/check.h"

namespace caustic {
namespace {

// Ranges this small are scanned in a loop instead of split further by the search.
constexpr uint32_t kLeafSize = 8;
// Up to this k, nearest() keeps its neighbours in a sorted array; above it, in a heap.
constexpr size_t kSortedInsertionK = 64;
// Ranges larger than this are built as OpenMP tasks.
constexpr uint32_t kParallelSize = 1u << 15;

}  // namespace

PhotonKdTree::PhotonKdTree(const std::vector<Vec3>& points) {
    CAUSTIC_CHECK(points.size() <= kIdMask);
    nodes_.resize(points.size());
    for (size_t i = 0; i < points.size(); ++i) nodes_[i] = Node{points[i], uint32_t(i)};
#pragma omp parallel
#pragma omp single
    build(0, uint32_t(nodes_.size()), 0);
}

void PhotonKdTree::build(uint32_t lo, uint32_t hi, int depth) {
    if (hi - lo <= 1) return;
    Bounds3 b;
    for (uint32_t i = lo; i < hi; ++i) b.extend(nodes_[i].p);
    Vec3 extent = b.hi - b.lo;
    int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    uint32_t mid = lo + (hi - lo) / 2;
    // Ties on the axis are ordered by input index, so that the tree is the same on every run.
    std::nth_element(nodes_.begin() + lo, nodes_.begin() + mid, nodes_.begin() + hi,
                     [axis](const Node& a, const Node& c) {
                         return a.p[axis] < c.p[axis] ||
                                (a.p[axis] == c.p[axis] && a.id() < c.id());
                     });
    nodes_[mid].idAxis = nodes_[mid].id() | (uint32_t(axis) << 30);
    if (hi - lo > kParallelSize) {
#pragma omp task
        build(lo, mid, depth + 1);
#pragma omp task
        build(mid + 1, hi, depth + 1);
#pragma omp taskwait
    } else {
        build(lo, mid, depth + 1);
        build(mid + 1, hi, depth + 1);
    }
}

// Visits every point that may lie within sqrt(bound2) of p; `visit` may shrink bound2. A far side
// is skipped only when its splitting plane is farther than the bound: every point beyond a plane
// at distance d has dist2 >= d^2, exactly also in float (distance2 adds d^2 to non-negative
// terms), so no point within the bound, ties included, is missed.
template <typename Visit>
void PhotonKdTree::search(const Vec3& p, float& bound2, Visit&& visit) const {
    // A range still to search and the squared distance of its nearest possible point.
    struct Range {
        uint32_t lo, hi;
        float min2;
    };
    Range stack[64];  // one entry per level at most: the depth of 2^30 points is 31
    int top = 0;
    stack[top++] = {0, uint32_t(nodes_.size()), 0.0f};
    while (top > 0) {
        Range r = stack[--top];
        if (r.min2 > bound2) continue;
        if (r.hi - r.lo <= kLeafSize) {
            for (uint32_t i = r.lo; i < r.hi; ++i) visit(nodes_[i]);
            continue;
        }
        uint32_t mid = r.lo + (r.hi - r.lo) / 2;
        const Node& node = nodes_[mid];
        visit(node);
        float d = p[node.axis()] - node.p[node.axis()];
        float d2 = std::max(r.min2, d * d);
        Range nearSide = d < 0.0f ? Range{r.lo, mid, r.min2} : Range{mid + 1, r.hi, r.min2};
        Range farSide = d < 0.0f ? Range{mid + 1, r.hi, d2} : Range{r.lo, mid, d2};
        // The far side goes on the stack first, so the near side is searched first and shrinks
        // the bound; the far side is tested against the bound again when it is popped.
        if (d2 <= bound2 && farSide.lo < farSide.hi) stack[top++] = farSide;
        if (nearSide.lo < nearSide.hi) stack[top++] = nearSide;
    }
}

void PhotonKdTree::nearest(const Vec3& p, int k, float maxDist2, std::vector<Neighbor>& out) const {
    out.clear();
    if (k <= 0 || nodes_.empty()) return;
    const auto limit = size_t(k);
    float bound2 = maxDist2;
    if (limit <= kSortedInsertionK) {
        // `out` stays sorted and at most k long: a new neighbour enters from the back and moves
        // forward past worse ones: no heap sifting and no final sort.
        search(p, bound2, [&](const Node& node) {
            Neighbor n{distance2(node.p, p), node.id()};
            if (!(n.dist2 <= maxDist2)) return;
            if (out.size() < limit) {
                out.push_back(n);
            } else if (n < out.back()) {
                out.back() = n;
            } else {
                return;
            }
            for (size_t i = out.size() - 1; i > 0 && out[i] < out[i - 1]; --i)
                std::swap(out[i], out[i - 1]);
            if (out.size() == limit) bound2 = out.back().dist2;
        });
        return;
    }
    // Large k: insertion would cost O(k) a photon, so `out` is a max-heap by the neighbour order
    // whose front is the worst of the k best so far, sorted at the end.
    search(p, bound2, [&](const Node& node) {
        Neighbor n{distance2(node.p, p), node.id()};
        if (!(n.dist2 <= maxDist2)) return;
        if (offerToHeap(out, limit, n) && out.size() == limit) bound2 = out.front().dist2;
    });
    std::sort_heap(out.begin(), out.end());
}

void PhotonKdTree::withinRadius(const Vec3& p, float radius2, std::vector<Neighbor>& out) const {
    out.clear();
    float bound2 = radius2;
    search(p, bound2, [&](const Node& node) {
        float d2 = distance2(node.p, p);
        if (d2 <= radius2) out.push_back(Neighbor{d2, node.id()});
    });
    std::sort(out.begin(), out.end());
}

int PhotonKdTree::depth() const {
    int d = 0;
    for (size_t n = nodes_.size(); n > 0; n /= 2) ++d;
    return d;
}

}  // namespace caustic
