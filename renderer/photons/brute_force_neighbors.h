// The reference neighbour index: every point for every query.
#pragma once

#include "photons/neighbor_index.h"

namespace caustic {

class BruteForceNeighbors final : public NeighborIndex {
public:
    explicit BruteForceNeighbors(std::vector<Vec3> points) : points_(std::move(points)) {}

    void nearest(const Vec3& p, int k, float maxDist2, std::vector<Neighbor>& out) const override;
    void withinRadius(const Vec3& p, float radius2, std::vector<Neighbor>& out) const override;
    size_t size() const override { return points_.size(); }
    size_t memoryBytes() const override { return points_.capacity() * sizeof(Vec3); }

private:
    std::vector<Vec3> points_;
};

}  // namespace caustic
