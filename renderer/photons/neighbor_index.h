// Nearest-neighbour queries over a fixed set of points (photon positions): the k nearest, or all
// within a radius. Implementations: PhotonKdTree (ours, for rendering) and BruteForceNeighbors (the
// reference it is tested against). Built once, then const and thread-safe.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/math.h"

namespace caustic {

/// A point found by a query: its squared distance and its index in the constructor's input.
struct Neighbor {
    float dist2;
    uint32_t id;

    /// The one order every index uses: by distance, ties by index. It makes the neighbour set of
    /// a query unique even among duplicated points, so implementations return identical sets.
    friend bool operator<(const Neighbor& a, const Neighbor& b) {
        return a.dist2 < b.dist2 || (a.dist2 == b.dist2 && a.id < b.id);
    }
    friend bool operator==(const Neighbor& a, const Neighbor& b) {
        return a.dist2 == b.dist2 && a.id == b.id;
    }
};

class NeighborIndex {
public:
    virtual ~NeighborIndex() = default;

    /// The k smallest neighbours (by the order above) with dist2 <= maxDist2, sorted, into `out`
    /// (cleared first). Fewer than k when fewer points are that close. Thread-safe.
    virtual void nearest(const Vec3& p, int k, float maxDist2,
                         std::vector<Neighbor>& out) const = 0;
    /// Every point with dist2 <= radius2, sorted, into `out` (cleared first). Thread-safe.
    virtual void withinRadius(const Vec3& p, float radius2, std::vector<Neighbor>& out) const = 0;

    virtual size_t size() const = 0;
    /// Bytes held beyond the caller's points.
    virtual size_t memoryBytes() const = 0;
};

/// Squared distance in float, computed the same way by every implementation (so that ties and the
/// dist2 <= bound tests agree to the bit).
inline float squaredLength(const Vec3& d) {
    return d.x * d.x + d.y * d.y + d.z * d.z;
}
inline float distance2(const Vec3& a, const Vec3& b) {
    return squaredLength(a - b);
}

/// Offers `n` to `heap`, a max-heap by the neighbour order holding the best (at most) k so far,
/// whose front is the worst of them. Returns whether `n` entered.
inline bool offerToHeap(std::vector<Neighbor>& heap, size_t k, const Neighbor& n) {
    if (heap.size() < k) {
        heap.push_back(n);
        std::push_heap(heap.begin(), heap.end());
        return true;
    }
    if (!(n < heap.front())) return false;
    std::pop_heap(heap.begin(), heap.end());
    heap.back() = n;
    std::push_heap(heap.begin(), heap.end());
    return true;
}

}  // namespace caustic
