// A balanced kd-tree over photon positions in one flat array (Jensen 2001, "Realistic Image
// Synthesis Using Photon Mapping", 6.3; Bentley 1975): the node of a range [lo, hi) is the median
// element at (lo + hi) / 2 on the axis of the range's largest extent, so the tree needs no
// pointers, no child indices and no padding, 16 bytes a point. Queries walk it near side first
// and skip a far side whose splitting plane is beyond the current search radius.
#pragma once

#include "photons/neighbor_index.h"

namespace caustic {

class PhotonKdTree final : public NeighborIndex {
public:
    /// Builds over `points` (at most 2^30 of them), in parallel for large inputs.
    explicit PhotonKdTree(const std::vector<Vec3>& points);

    void nearest(const Vec3& p, int k, float maxDist2, std::vector<Neighbor>& out) const override;
    void withinRadius(const Vec3& p, float radius2, std::vector<Neighbor>& out) const override;
    size_t size() const override { return nodes_.size(); }
    size_t memoryBytes() const override { return nodes_.capacity() * sizeof(Node); }

    /// Depth of the tree: ceil(log2(n + 1)) for n points.
    int depth() const;

private:
    // A point with its input index; the two top bits of `idAxis` hold the splitting axis.
    struct Node {
        Vec3 p;
        uint32_t idAxis;
        uint32_t id() const { return idAxis & kIdMask; }
        int axis() const { return int(idAxis >> 30); }
    };
    static constexpr uint32_t kIdMask = (1u << 30) - 1;

    void build(uint32_t lo, uint32_t hi, int depth);
    template <typename Visit>
    void search(const Vec3& p, float& bound2, Visit&& visit) const;

    std::vector<Node> nodes_;
};

}  // namespace caustic
