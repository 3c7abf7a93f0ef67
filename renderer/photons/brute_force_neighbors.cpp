#include "photons/brute_force_neighbors.h"

#include <algorithm>

namespace caustic {

void BruteForceNeighbors::nearest(const Vec3& p, int k, float maxDist2,
                                  std::vector<Neighbor>& out) const {
    out.clear();
    if (k <= 0) return;
    // One scan with a max-heap of the k best so far: O(n log k), the fair baseline for a tree.
    for (size_t i = 0; i < points_.size(); ++i) {
        Neighbor n{distance2(points_[i], p), uint32_t(i)};
        if (n.dist2 <= maxDist2) offerToHeap(out, size_t(k), n);
    }
    std::sort_heap(out.begin(), out.end());
}

void BruteForceNeighbors::withinRadius(const Vec3& p, float radius2,
                                       std::vector<Neighbor>& out) const {
    out.clear();
    for (size_t i = 0; i < points_.size(); ++i) {
        float d2 = distance2(points_[i], p);
        if (d2 <= radius2) out.push_back(Neighbor{d2, uint32_t(i)});
    }
    std::sort(out.begin(), out.end());
}

}  // namespace caustic
