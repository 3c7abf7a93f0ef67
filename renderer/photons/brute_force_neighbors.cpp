#include "photons/brute_force_neighbors.h"

#include <algorithm>

namespace caustic {

void BruteForceNeighbors::nearest(const Vec3& p, int k, float maxDist2,
                                  std::vector<Neighbor>& out) const {
    withinRadius(p, maxDist2, out);
    if (out.size() > size_t(std::max(k, 0))) out.resize(size_t(std::max(k, 0)));
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
