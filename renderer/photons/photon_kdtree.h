// A kd-tree over photon positions for k-nearest and fixed-radius look-ups. Ranges of more than
// kLeafSize points split at the median of their largest extent (Bentley 1975; Jensen 2001,
// "Realistic Image Synthesis Using Photon Mapping", 6.3), so the tree is balanced and implicit: a
// range [lo, hi) has children [lo, mid) and [mid, hi), mid = (lo + hi) / 2, and its split (axis,
// plane) sits in an array in heap order. Leaves hold only points, each leaf's in one contiguous
// block laid out by coordinate (all x, then all y and z), so a leaf's distances are computed as
// one fixed-width vector loop. Queries keep p's offset from each cell on
// every axis, the cell's exact distance (as nanoflann does), and skip cells beyond the bound.
#pragma once

#include "photons/neighbor_index.h"

namespace caustic {

class PhotonKdTree final : public NeighborIndex {
public:
    /// Points a leaf holds at most.
    static constexpr uint32_t kLeafSize = 16;

    /// Builds over `points` (fewer than 2^31 of them), in parallel for large inputs.
    explicit PhotonKdTree(const std::vector<Vec3>& points);

    void nearest(const Vec3& p, int k, float maxDist2, std::vector<Neighbor>& out) const override;
    void withinRadius(const Vec3& p, float radius2, std::vector<Neighbor>& out) const override;
    size_t size() const override { return size_; }
    size_t memoryBytes() const override {
        return coords_.capacity() * sizeof(float) + ids_.capacity() * sizeof(uint32_t) +
               splits_.capacity() * sizeof(Split);
    }

    /// Levels of splits: 0 for at most kLeafSize points, one more each time the count doubles.
    int depth() const { return depth_; }

private:
    // The splitting plane of an inner range: points left of it have coordinate <= value on the
    // axis, points right of it >= value.
    struct Split {
        float value;
        uint32_t axis;
    };
    struct Point {
        Vec3 p;
        uint32_t id;
    };

    void build(std::vector<Point>& points, uint32_t lo, uint32_t hi, uint32_t node);
    template <typename Visit>
    void search(const Vec3& p, float& bound2, Visit&& visit) const;

    size_t size_ = 0;
    int depth_ = 0;
    std::vector<Split> splits_;  // heap order: the children of node i are 2i + 1 and 2i + 2
    // A leaf [lo, hi) of n points: x[n], y[n], z[n] from coords_[3 lo], then kLeafSize - 1
    // floats of padding at the end, so that a leaf's distances are always computed kLeafSize
    // wide (one fixed vector loop; the lanes past n are not used). ids_ in the same order.
    std::vector<float> coords_;
    std::vector<uint32_t> ids_;
};

}  // namespace caustic
