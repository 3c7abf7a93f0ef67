// The SAH build. Large nodes choose their split from 32 bins of primitive bounds per axis (O(n)
// per node, so O(N log N) in all; Popov et al. 2006, "Experiences with Streaming Construction of
// SAH KD-Trees"); nodes of up to kExactLimit references sweep every primitive boundary exactly
// (pbrt-v3 4.4.2). The top of the tree is built in parallel with OpenMP tasks.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "accel/kdtree/clip.h"
#include "accel/kdtree/kdtree.h"
#include "core/check.h"

namespace caustic {
namespace {

constexpr int kBins = 32;
constexpr size_t kExactLimit = 64;
constexpr size_t kParallelLimit = 4096;

struct Ref {
    Bounds3 b;
    uint32_t prim;
};

struct Split {
    int axis = -1;
    float pos = 0.0f;
    double cost = std::numeric_limits<double>::infinity();
};

struct BuildNode {
    int axis = 3;  // 3: leaf
    float split = 0.0f;
    std::unique_ptr<BuildNode> below, above;
    std::vector<uint32_t> prims;
};

Bounds3 childBox(const Bounds3& box, int axis, float pos, bool above) {
    Bounds3 b = box;
    (above ? b.lo : b.hi)[axis] = pos;
    return b;
}

// Box sizes and areas are taken in double: float coordinates of a box can lie up to 2 FLT_MAX
// apart (a sphere of radius 3e38), and the area overflows float from 1.8e19 on.
glm::dvec3 diagonal(const Bounds3& b) {
    return glm::dvec3(b.hi) - glm::dvec3(b.lo);
}
double surfaceArea(const Bounds3& b) {
    if (b.empty()) return 0.0;
    glm::dvec3 d = diagonal(b);
    return 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
}

// A primitive's box cut at +-FLT_MAX: the part beyond (a sphere of radius 3e38 at 3e38) has no
// float coordinates for a ray to reach, and every box of the tree then stays finite.
Bounds3 finiteBox(const Bounds3& b) {
    const Vec3 m(std::numeric_limits<float>::max());
    return Bounds3{glm::clamp(b.lo, -m, m), glm::clamp(b.hi, -m, m)};
}

// The bin of a position scaled to [0, kBins), clamped in double before the conversion to int,
// which is undefined for NaN and out-of-range values.
int binOf(double scaled) {
    return scaled >= 0.0 ? int(std::min(scaled, double(kBins - 1))) : 0;
}

}  // namespace

class KdTreeBuilder {
public:
    KdTreeBuilder(KdTreeAccel& tree, const KdTreeOptions& options)
        : tree_(tree), geometry_(tree.geometry_), options_(options) {}

    void build() {
        uint32_t n = geometry_.size();
        std::vector<Ref> refs(n);
        Bounds3 box;
        for (uint32_t p = 0; p < n; ++p) {
            refs[p] = Ref{finiteBox(fuzzyBounds(geometry_, p)), p};
            box.extend(refs[p].b);
        }
        tree_.bounds_ = box;
        int maxDepth = options_.maxDepth > 0
                           ? options_.maxDepth
                           : int(std::lround(8 + 1.3 * std::log2(std::max<uint32_t>(n, 1))));
        maxDepth = std::min(maxDepth, KdTreeAccel::kMaxDepth);

        BuildNode root;
#pragma omp parallel
#pragma omp single nowait
        buildNode(root, std::move(refs), box, maxDepth, 0);

        rootArea_ = surfaceArea(box);
        flatten(root, box, 0);
    }

private:
    // The SAH cost of splitting `box` on one axis, with what it needs computed once per node and
    // axis rather than once per candidate plane (a node of n references has 2n of them).
    class SplitCost {
    public:
        SplitCost(const KdTreeOptions& options, const Bounds3& box, int axis)
            : options_(options), lo_(box.lo[axis]), hi_(box.hi[axis]) {
            const glm::dvec3 d = diagonal(box);
            const int o1 = (axis + 1) % 3, o2 = (axis + 2) % 3;
            const double invArea = 1.0 / surfaceArea(box);
            cap_ = 2.0 * d[o1] * d[o2] * invArea;
            ring_ = 2.0 * (d[o1] + d[o2]) * invArea;
        }
        double operator()(float pos, size_t nBelow, size_t nAbove) const {
            const double below = cap_ + (double(pos) - lo_) * ring_;
            const double above = cap_ + (hi_ - double(pos)) * ring_;
            const double bonus = (nBelow == 0 || nAbove == 0) ? options_.emptyBonus : 0.0;
            return options_.traversalCost + options_.intersectCost * (1.0 - bonus) *
                                                (below * double(nBelow) + above * double(nAbove));
        }

    private:
        const KdTreeOptions& options_;
        double lo_, hi_, cap_ = 0, ring_ = 0;
    };

    // Counts each axis' starts and ends per bin in one pass over the references (each is read
    // once, not once per axis), then sweeps every axis' bin edges.
    Split findBinned(const std::vector<Ref>& refs, const Bounds3& box) const {
        double lo[3], extent[3], scale[3];
        for (int axis = 0; axis < 3; ++axis) {
            lo[axis] = box.lo[axis];
            extent[axis] = double(box.hi[axis]) - lo[axis];
            scale[axis] = extent[axis] > 0.0 ? kBins / extent[axis] : 0.0;
        }
        size_t starts[3][kBins] = {}, ends[3][kBins] = {};
        for (const Ref& r : refs) {
            for (int axis = 0; axis < 3; ++axis) {
                ++starts[axis][binOf((r.b.lo[axis] - lo[axis]) * scale[axis])];
                ++ends[axis][binOf((r.b.hi[axis] - lo[axis]) * scale[axis])];
            }
        }
        Split best;
        for (int axis = 0; axis < 3; ++axis) {
            if (!(extent[axis] > 0.0)) continue;
            const SplitCost cost(options_, box, axis);
            size_t nBelow = 0, nAbove = refs.size();
            for (int i = 1; i < kBins; ++i) {
                nBelow += starts[axis][i - 1];
                nAbove -= ends[axis][i - 1];
                auto pos = float(lo[axis] + extent[axis] * i / kBins);
                // A box a few floats wide has bin edges that round onto its faces.
                if (!(pos > box.lo[axis] && pos < box.hi[axis])) continue;
                double c = cost(pos, nBelow, nAbove);
                if (c < best.cost) best = Split{axis, pos, c};
            }
        }
        return best;
    }

    // The exact sweep over every primitive boundary (pbrt-v3 4.4.2): the starts and the ends of
    // the references sorted apart, as plain floats, and merged in the sweep, starts first at equal
    // positions (the order of pbrt-v3's sorted events, without sorting them as pairs).
    Split findExact(const std::vector<Ref>& refs, const Bounds3& box) const {
        const size_t n = refs.size();
        float starts[kExactLimit], ends[kExactLimit];
        Split best;
        for (int axis = 0; axis < 3; ++axis) {
            if (!(box.hi[axis] > box.lo[axis])) continue;
            for (size_t i = 0; i < n; ++i) {
                starts[i] = refs[i].b.lo[axis];
                ends[i] = refs[i].b.hi[axis];
            }
            std::sort(starts, starts + n);
            std::sort(ends, ends + n);
            const SplitCost cost(options_, box, axis);
            size_t nBelow = 0, nAbove = n;
            for (size_t i = 0, j = 0; i < n || j < n;) {
                const bool start = i < n && (j == n || starts[i] <= ends[j]);
                const float pos = start ? starts[i] : ends[j];
                if (!start) --nAbove;
                if (pos > box.lo[axis] && pos < box.hi[axis]) {
                    double c = cost(pos, nBelow, nAbove);
                    if (c < best.cost) best = Split{axis, pos, c};
                }
                if (start) {
                    ++nBelow;
                    ++i;
                } else {
                    ++j;
                }
            }
        }
        return best;
    }

    // Sends each reference to the side(s) of the plane it overlaps, clipped to that side's box.
    void partition(std::vector<Ref>& refs, const Bounds3& box, int axis, float pos,
                   std::vector<Ref>& below, std::vector<Ref>& above) const {
        Bounds3 belowBox = childBox(box, axis, pos, false),
                aboveBox = childBox(box, axis, pos, true);
        below.reserve(refs.size());
        above.reserve(refs.size());
        for (const Ref& r : refs) {
            float lo = r.b.lo[axis], hi = r.b.hi[axis];
            if (lo == pos && hi == pos) {
                // Lying in the plane: both sides, so rays in or through the plane find it.
                below.push_back(r);
                above.push_back(r);
            } else if (hi <= pos) {
                below.push_back(r);
            } else if (lo >= pos) {
                above.push_back(r);
            } else {
                for (bool isAbove : {false, true}) {
                    const Bounds3& child = isAbove ? aboveBox : belowBox;
                    Bounds3 clipped =
                        options_.clipPrimitives
                            ? clipPrimitive(geometry_, r.prim, child)
                            : Bounds3{glm::max(r.b.lo, child.lo), glm::min(r.b.hi, child.hi)};
                    clipped = Bounds3{glm::max(clipped.lo, r.b.lo), glm::min(clipped.hi, r.b.hi)};
                    if (!clipped.empty()) (isAbove ? above : below).push_back(Ref{clipped, r.prim});
                }
            }
        }
        refs.clear();
        refs.shrink_to_fit();
    }

    void makeLeaf(BuildNode& node, const std::vector<Ref>& refs) const {
        node.axis = 3;
        node.prims.reserve(refs.size());
        for (const Ref& r : refs) node.prims.push_back(r.prim);
    }

    void buildNode(BuildNode& node, std::vector<Ref> refs, const Bounds3& box, int depthLeft,
                   int badRefines) {
        size_t n = refs.size();
        if (n <= 1 || depthLeft == 0 || !(surfaceArea(box) > 0.0)) return makeLeaf(node, refs);

        // Choose the split; stop when splitting does not pay (pbrt-v3's rule, allowing a few bad
        // refinements since a worse split can enable better ones below).
        Split split = n > kExactLimit ? findBinned(refs, box) : findExact(refs, box);
        double leafCost = options_.intersectCost * double(n);
        if (split.cost > leafCost) ++badRefines;
        if (split.axis < 0 || (split.cost > 4.0f * leafCost && n < 16) || badRefines == 3)
            return makeLeaf(node, refs);

        std::vector<Ref> below, above;
        partition(refs, box, split.axis, split.pos, below, above);
        // A split that moved nothing is a loop: stop.
        if (below.size() == n && above.size() == n) {
            makeLeaf(node, below);
            return;
        }
        node.axis = split.axis;
        node.split = split.pos;
        node.below = std::make_unique<BuildNode>();
        node.above = std::make_unique<BuildNode>();
        Bounds3 belowBox = childBox(box, split.axis, split.pos, false);
        Bounds3 aboveBox = childBox(box, split.axis, split.pos, true);
        if (n >= kParallelLimit) {
#pragma omp task default(shared) firstprivate(belowBox, depthLeft, badRefines)
            buildNode(*node.below, std::move(below), belowBox, depthLeft - 1, badRefines);
            buildNode(*node.above, std::move(above), aboveBox, depthLeft - 1, badRefines);
#pragma omp taskwait
        } else {
            buildNode(*node.below, std::move(below), belowBox, depthLeft - 1, badRefines);
            buildNode(*node.above, std::move(above), aboveBox, depthLeft - 1, badRefines);
        }
    }

    // Writes the tree depth-first: a node's below child follows it, its above child's index is
    // stored in the node. Frees the build nodes on the way.
    void flatten(BuildNode& node, const Bounds3& box, uint32_t depth) {
        KdTreeStats& stats = tree_.stats_;
        stats.maxDepth = std::max(stats.maxDepth, depth);
        auto index = uint32_t(tree_.nodes_.size());
        tree_.nodes_.emplace_back();
        double areaRatio = rootArea_ > 0.0 ? surfaceArea(box) / rootArea_ : 0.0;
        if (node.axis == 3) {
            auto count = uint32_t(node.prims.size());
            CAUSTIC_CHECK_LT(count, 1u << 30);
            KdTreeAccel::Node& leaf = tree_.nodes_[index];
            leaf.bits = 3u | (count << 2);
            if (count == 1) {
                leaf.onePrim = node.prims[0];
            } else {
                leaf.primOffset = uint32_t(tree_.primIndices_.size());
                tree_.primIndices_.insert(tree_.primIndices_.end(), node.prims.begin(),
                                          node.prims.end());
            }
            ++stats.leaves;
            if (count == 0) ++stats.emptyLeaves;
            stats.references += count;
            stats.sahCost +=
                options_.intersectCost * double(count) * areaRatio / options_.traversalCost;
            return;
        }
        ++stats.interiorNodes;
        stats.sahCost += areaRatio;
        int axis = node.axis;
        float split = node.split;
        flatten(*node.below, childBox(box, axis, split, false), depth + 1);
        node.below.reset();
        auto above = uint32_t(tree_.nodes_.size());
        CAUSTIC_CHECK_LT(above, 1u << 30);
        tree_.nodes_[index].split = split;
        tree_.nodes_[index].bits = uint32_t(axis) | (above << 2);
        flatten(*node.above, childBox(box, axis, split, true), depth + 1);
        node.above.reset();
    }

    KdTreeAccel& tree_;
    const Geometry& geometry_;
    KdTreeOptions options_;
    double rootArea_ = 0.0;
};

KdTreeAccel::KdTreeAccel(const Geometry& geometry, const KdTreeOptions& options)
    : geometry_(geometry) {
    static_assert(sizeof(Node) == 8);
    KdTreeBuilder(*this, options).build();
    if (geometry.hasTriangles()) {
        triangles_.resize(geometry.size());
        for (uint32_t p = 0; p < geometry.size(); ++p) {
            TriangleVertices& v = triangles_[p];
            if (geometry.kind(p) == PrimKind::Triangle)
                geometry.triangleVertices(geometry.localIndex(p), v.p0, v.p1, v.p2);
        }
    }
}

size_t KdTreeAccel::memoryBytes() const {
    return nodes_.capacity() * sizeof(Node) + primIndices_.capacity() * sizeof(uint32_t) +
           triangles_.capacity() * sizeof(TriangleVertices);
}

}  // namespace caustic
