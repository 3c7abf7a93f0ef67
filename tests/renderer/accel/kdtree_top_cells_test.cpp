// The kd-tree's top cells (accel/kdtree/top_cells.h): a ray enters only the cells whose boxes it
// meets, in the order of its direction's octant, with its range clipped to each box. That is
// right only if every primitive part a subtree holds lies in its cell's box, if every leaf with
// primitives is in exactly one cell, and if the order is front to back; and then a tree finds the
// same hits whatever its top depth.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <optional>
#include <vector>

#include "accel/kdtree/kdtree.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "scene/mesh_loader.h"

namespace caustic {
namespace {

using Node = KdTreeAccel::Node;

Geometry bunny() {
    const TriangleMesh mesh =
        loadObj(std::string(CAUSTIC_DEFAULT_ASSETS_DIR) + "/stanford-bunny.obj", MeshTransform{},
                "/meshes/stanford-bunny.obj");
    Geometry geometry;
    geometry.addTriangles(mesh.positions, mesh.triangles, 0);
    return geometry;
}

// Rays with origins in the bounds grown by half about their centre and uniform directions, as
// bench_accel_rays' incoherent set: many cross the bounds and miss, as many hit.
std::vector<Ray> incoherentRays(const Bounds3& bounds, int n) {
    Rng rng(7);
    const Vec3 lo = bounds.center() - 0.75f * bounds.diagonal(), size = 1.5f * bounds.diagonal();
    std::vector<Ray> rays(static_cast<size_t>(n));
    for (Ray& r : rays) {
        r.o = lo + Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * size;
        r.d = sampleUniformSphere(Vec2(rng.uniform(), rng.uniform()));
    }
    return rays;
}

bool contains(const Bounds3& outer, const Bounds3& inner) {
    for (int a = 0; a < 3; ++a)
        if (component(inner.lo, a) < component(outer.lo, a) ||
            component(inner.hi, a) > component(outer.hi, a))
            return false;
    return true;
}

// Each leaf under `index`: calls visit(leaf node).
template <class Visit>
void forEachLeaf(std::span<const Node> nodes, uint32_t index, Visit&& visit) {
    const Node& node = nodes[index];
    if (node.isLeaf()) {
        visit(node);
        return;
    }
    forEachLeaf(nodes, index + 1, visit);
    forEachLeaf(nodes, node.aboveChild(), visit);
}

TEST(KdTopCells, HoldEveryLeafWithPrimitivesOnceInABoxAroundItsBlocks) {
    const Geometry geometry = bunny();
    for (int depth = 0; depth <= KdTopCells::kMaxDepth; ++depth) {
        SCOPED_TRACE(depth);
        const KdTreeAccel tree(geometry, KdTreeOptions{.topDepth = depth});
        const std::span<const Node> nodes = tree.nodes();
        const uint32_t* data = tree.leafData().data();
        size_t leavesWithPrimitives = 0;
        for (const Node& n : nodes) leavesWithPrimitives += n.isLeaf() && n.primCount() > 0;

        std::vector<uint32_t> firstRoots;
        for (uint32_t negative = 0; negative < 8; ++negative) {
            const KdTopCells::Octant& octant = tree.topCells().octants[negative];
            ASSERT_EQ(octant.roots.size(), octant.count);
            EXPECT_LE(octant.count, 1u << depth);
            EXPECT_EQ(octant.count, tree.stats().topCells);
            EXPECT_EQ(octant.stride % kd_leaf::kLanes, 0u);
            EXPECT_GE(octant.stride, octant.count);
            size_t leaves = 0;
            for (uint32_t c = 0; c < octant.count; ++c) {
                const Bounds3 box = loadBoxInRows(octant.bounds.data(), octant.stride, c);
                forEachLeaf(nodes, octant.roots[c], [&](const Node& leaf) {
                    const uint32_t n = leaf.primCount();
                    leaves += n > 0;
                    for (uint32_t b = 0; b < kd_leaf::blocks(n); ++b) {
                        const Bounds3 block =
                            loadBoxInRows(data + leaf.leafOffset + kd_leaf::blockBound(n, 0, 0),
                                          kd_leaf::blocks(n), b);
                        EXPECT_TRUE(contains(box, block)) << "cell " << c << ", block " << b;
                    }
                });
            }
            // Cells are disjoint subtrees: each leaf with primitives counted once.
            EXPECT_EQ(leaves, leavesWithPrimitives);
            std::vector<uint32_t> roots = octant.roots;
            std::ranges::sort(roots);
            if (negative == 0) firstRoots = roots;
            EXPECT_EQ(roots, firstRoots) << "octant " << negative;
        }
    }
}

// The traversal pops the cells a ray meets in its octant's order and stops at the first whose
// range begins beyond the closest hit: their ranges must begin in that order.
TEST(KdTopCells, ComeFrontToBackInTheirOctantsOrder) {
    const Geometry geometry = bunny();
    const KdTreeAccel tree(geometry);
    ASSERT_GT(tree.stats().topCells, 16u);
    int rayCrossingCells = 0;
    for (const Ray& ray : incoherentRays(tree.bounds(), 20000)) {
        const uint32_t negative = directionSignBits(ray.d);
        const KdTopCells::Octant& octant = tree.topCells().octants[negative];
        const Vec3 invDir = 1.0f / ray.d;
        float previous = 0.0f;
        int met = 0;
        for (uint32_t c = 0; c < octant.count; ++c) {
            float t0 = 0.0f, t1 = kInfinity;
            if (!clipToBox(loadBoxInRows(octant.bounds.data(), octant.stride, c), ray.o, invDir,
                           negative, t0, t1))
                continue;
            ASSERT_GE(t0, previous * (1.0f - kRayBoxSlack)) << "cell " << c;
            previous = t0;
            ++met;
        }
        rayCrossingCells += met > 1;
    }
    EXPECT_GT(rayCrossingCells, 2000);
}

// A tree finds the same closest hits, distance and primitive, and the same occlusion, with top
// cells of every depth as with the whole tree one cell.
TEST(KdTopCells, FindTheSameHitsAtEveryDepth) {
    const Geometry geometry = bunny();
    const KdTreeAccel whole(geometry, KdTreeOptions{.topDepth = 0});
    const std::vector<Ray> rays = incoherentRays(whole.bounds(), 20000);
    std::vector<std::optional<Hit>> expected;
    int hits = 0;
    for (const Ray& ray : rays) {
        expected.push_back(whole.intersect(ray, kInfinity));
        hits += expected.back().has_value();
    }
    EXPECT_GT(hits, 2000);
    for (int depth = 1; depth <= KdTopCells::kMaxDepth; ++depth) {
        SCOPED_TRACE(depth);
        const KdTreeAccel tree(geometry, KdTreeOptions{.topDepth = depth});
        for (size_t i = 0; i < rays.size(); ++i) {
            const std::optional<Hit> hit = tree.intersect(rays[i], kInfinity);
            ASSERT_EQ(hit.has_value(), expected[i].has_value()) << "ray " << i;
            ASSERT_EQ(tree.occluded(rays[i], kInfinity), hit.has_value()) << "ray " << i;
            if (!hit) continue;
            ASSERT_EQ(hit->t, expected[i]->t) << "ray " << i;
            ASSERT_EQ(hit->prim, expected[i]->prim) << "ray " << i;
        }
    }
}

}  // namespace
}  // namespace caustic
