#include "photons/photon_kdtree.h"

#include <algorithm>
#include <bit>

#if defined(__AVX__)
#include <immintrin.h>
#endif

#include "core/bounds.h"
#include "core/check.h"

namespace caustic {
namespace {

// Up to this k, nearest() keeps its neighbours in a sorted array; above it, in a heap.
constexpr size_t kSortedInsertionK = 128;
// Ranges larger than this are built as OpenMP tasks.
constexpr uint32_t kParallelSize = 1u << 15;
// A cell's squared distance is scaled by this before it is compared with the bound, so that a
// rounding that differs between it and a point's distance2 (contracted into FMAs in one place
// and not the other) never skips a point at exactly the bound. It visits a few more cells.
constexpr float kCellShrink = 1.0f - 0x1p-20f;

bool isLeaf(uint32_t lo, uint32_t hi) {
    return hi - lo <= PhotonKdTree::kLeafSize;
}

int splitLevels(size_t n) {
    int levels = 0;
    for (; n > PhotonKdTree::kLeafSize; n = n - n / 2) ++levels;
    return levels;
}

}  // namespace

PhotonKdTree::PhotonKdTree(const std::vector<Vec3>& points)
    : size_(points.size()), depth_(splitLevels(points.size())) {
    CAUSTIC_CHECK(points.size() < (size_t(1) << 31));
    std::vector<Point> work(points.size());
    for (size_t i = 0; i < points.size(); ++i) work[i] = Point{points[i], uint32_t(i)};
    splits_.resize((size_t(1) << depth_) - 1);
    if (!points.empty()) coords_.resize(3 * points.size() + 2 * (kLeafSize - 1), 0.0f);
    ids_.resize(points.size());
#pragma omp parallel
#pragma omp single
    build(work, 0, uint32_t(work.size()), 0);
}

void PhotonKdTree::build(std::vector<Point>& points, uint32_t lo, uint32_t hi, uint32_t node) {
    if (isLeaf(lo, hi)) {
        const uint32_t n = hi - lo;
        // data() + offset, not &coords_[offset]: an empty map's array is empty.
        float* leaf = coords_.data() + 3 * size_t(lo);
        for (uint32_t i = 0; i < n; ++i) {
            leaf[i] = points[lo + i].p.x;
            leaf[n + i] = points[lo + i].p.y;
            leaf[2 * n + i] = points[lo + i].p.z;
            ids_[lo + i] = points[lo + i].id;
        }
        return;
    }
    Bounds3 b;
    for (uint32_t i = lo; i < hi; ++i) b.extend(points[i].p);
    const Vec3 extent = b.hi - b.lo;
    const int axis =
        extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const uint32_t mid = lo + (hi - lo) / 2;
    // Ties on the axis are ordered by input index, so that the tree is the same on every run.
    std::nth_element(points.begin() + lo, points.begin() + mid, points.begin() + hi,
                     [axis](const Point& a, const Point& c) {
                         return a.p[axis] < c.p[axis] || (a.p[axis] == c.p[axis] && a.id < c.id);
                     });
    splits_[node] = Split{points[mid].p[axis], uint32_t(axis)};
    if (hi - lo > kParallelSize) {
#pragma omp task shared(points)
        build(points, lo, mid, 2 * node + 1);
#pragma omp task shared(points)
        build(points, mid, hi, 2 * node + 2);
#pragma omp taskwait
    } else {
        build(points, lo, mid, 2 * node + 1);
        build(points, mid, hi, 2 * node + 2);
    }
}

// Calls visit(dist2, id) for every point of every cell within sqrt(bound2) of p whose dist2 <=
// bound2; `visit` may shrink bound2. A cell's distance is exact, as in nanoflann (Arya and Mount
// 1993, "Algorithms for fast vector quantization"): a range carries p's offset from its cell on
// each axis, and a far side's offset on the splitting axis is p's distance to the plane, whatever
// it was before. Every point of a cell has each coordinate difference at least the cell's offset
// on that axis (subtraction and squaring round monotonically), so its dist2 is at least the
// cell's squared distance, up to the rounding kCellShrink allows for.
template <typename Visit>
void PhotonKdTree::search(const Vec3& p, float& bound2, Visit&& visit) const {
    struct Range {
        uint32_t lo, hi, node;
        float min2;
        Vec3 offset;
    };
    Range stack[64];  // one entry per level at most: fewer than 2^31 points have 31 levels
    int top = 0;
    if (size_ > 0) stack[top++] = {0, uint32_t(size_), 0, 0.0f, Vec3(0.0f)};
    while (top > 0) {
        const Range& popped = stack[--top];
        if (popped.min2 > bound2) continue;
        // The range in locals, not a Range: a Range built field by field and then copied whole
        // (one 16-byte load of four 4-byte stores) waits until the stores reach the cache.
        uint32_t lo = popped.lo, hi = popped.hi, node = popped.node;
        Vec3 offset = popped.offset;
        // (`popped` is read only up to here: the pushes below reuse its slot.)
        // Down to the leaf on p's side, leaving the far sides on the stack: they are searched
        // after it, nearest last pushed first, each tested against the bound it shrank to.
        while (!isLeaf(lo, hi)) {
            const uint32_t mid = lo + (hi - lo) / 2;
            const Split split = splits_[node];
            const float d = p[int(split.axis)] - split.value;
            // The far side's offset: this range's, with p's distance to the plane on the axis
            // (selected, not indexed, so that it stays in registers).
            const float ad = std::abs(d);
            const Vec3 far(split.axis == 0 ? ad : offset.x, split.axis == 1 ? ad : offset.y,
                           split.axis == 2 ? ad : offset.z);
            const float farMin2 = squaredLength(far) * kCellShrink;
            const bool left = d < 0.0f;
            const uint32_t farLo = left ? mid : lo, farHi = left ? hi : mid;
            const uint32_t farNode = 2 * node + (left ? 2 : 1);
            node = 2 * node + (left ? 1 : 2);
            (left ? hi : lo) = mid;
            if (farMin2 <= bound2) stack[top++] = Range{farLo, farHi, farNode, farMin2, far};
        }
        const uint32_t n = hi - lo;
        const float* x = coords_.data() + 3 * size_t(lo);
        const float* y = x + n;
        const float* z = y + n;
        float d2[kLeafSize];
        for (uint32_t i = 0; i < kLeafSize; ++i) d2[i] = squaredLength(Vec3(x[i], y[i], z[i]) - p);
        // The points within the bound as a mask, so that the loop below branches once a hit, not
        // once a point (whether a point is a hit is a coin toss the branch predictor loses).
        static_assert(kLeafSize == 16);
        uint32_t hits = 0;
#if defined(__AVX__)
        const __m256 b = _mm256_set1_ps(bound2);
        hits = uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(_mm256_loadu_ps(d2), b, _CMP_LE_OQ))) |
               uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(_mm256_loadu_ps(d2 + 8), b, _CMP_LE_OQ)))
                   << 8;
#else
        for (uint32_t i = 0; i < kLeafSize; ++i) hits |= uint32_t(d2[i] <= bound2) << i;
#endif
        // In index order, as before: nearest() shrinks the bound as it goes, so each is tested
        // again.
        for (hits &= (1u << n) - 1; hits != 0; hits &= hits - 1) {
            const auto i = uint32_t(std::countr_zero(hits));
            if (d2[i] <= bound2) visit(d2[i], ids_[lo + i]);
        }
    }
}

void PhotonKdTree::nearest(const Vec3& p, int k, float maxDist2, std::vector<Neighbor>& out) const {
    out.clear();
    if (k <= 0) return;
    const auto limit = size_t(k);
    float bound2 = maxDist2;
    if (limit <= kSortedInsertionK) {
        // A neighbour is one 64-bit key, its dist2's bits above its index: dist2 >= +0 (a sum
        // of squares), and the bits of non-negative floats order as the floats do, so one
        // integer comparison is the neighbour order. The first k found are taken as they come
        // and sorted once; after that `best` stays sorted: a better key is held in a register
        // while the worse ones move up a place, and is written once where it belongs (as
        // nanoflann's KNNResultSet does; swapping it forward step by step stalls on its own
        // stores, and inserting the first k one by one costs O(k^2)).
        uint64_t best[kSortedInsertionK];
        size_t count = 0;
        search(p, bound2, [&](float dist2, uint32_t id) {
            const uint64_t key = uint64_t(std::bit_cast<uint32_t>(dist2)) << 32 | id;
            if (count < limit) {
                best[count++] = key;
                if (count < limit) return;
                std::sort(best, best + limit);
            } else {
                if (key >= best[limit - 1]) return;
                size_t i = limit - 1;
                for (; i > 0 && key < best[i - 1]; --i) best[i] = best[i - 1];
                best[i] = key;
            }
            bound2 = std::bit_cast<float>(uint32_t(best[limit - 1] >> 32));
        });
        if (count < limit) std::sort(best, best + count);
        out.resize(count);
        for (size_t i = 0; i < count; ++i)
            out[i] = Neighbor{std::bit_cast<float>(uint32_t(best[i] >> 32)), uint32_t(best[i])};
        return;
    }
    // Large k: insertion would cost O(k) a photon, so `out` is a max-heap by the neighbour order
    // whose front is the worst of the k best so far, sorted at the end.
    search(p, bound2, [&](float dist2, uint32_t id) {
        if (offerToHeap(out, limit, Neighbor{dist2, id}) && out.size() == limit)
            bound2 = out.front().dist2;
    });
    std::sort_heap(out.begin(), out.end());
}

void PhotonKdTree::withinRadius(const Vec3& p, float radius2, std::vector<Neighbor>& out) const {
    out.clear();
    float bound2 = radius2;
    search(p, bound2, [&](float dist2, uint32_t id) { out.push_back(Neighbor{dist2, id}); });
    std::sort(out.begin(), out.end());
}

}  // namespace caustic
