// The kd-tree's build splits the top of the tree among OpenMP tasks; whatever thread builds which
// subtree, the tree must be the same, so that renders are bit-identical on any thread count.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cstring>
#include <iterator>
#include <span>
#include <vector>

#include "accel/kdtree/kdtree.h"
#include "renderer/accel/kdtree_variants.h"
#include "scene/mesh_loader.h"

namespace caustic {
namespace {

// The bytes of a tree: its nodes and its leaves' data.
std::vector<unsigned char> treeBytes(const KdTreeAccel& tree) {
    std::vector<unsigned char> bytes(tree.nodes().size_bytes() + tree.leafData().size_bytes());
    std::memcpy(bytes.data(), tree.nodes().data(), tree.nodes().size_bytes());
    std::memcpy(bytes.data() + tree.nodes().size_bytes(), tree.leafData().data(),
                tree.leafData().size_bytes());
    return bytes;
}

// An n x n x n grid of small shapes, one a unit cell: a sphere where isSphere(x, y, z), else a
// triangle.
template <class IsSphere>
void addGrid(Geometry& geometry, int n, IsSphere isSphere) {
    std::vector<Vec3> p;
    std::vector<glm::uvec3> tris;
    for (int x = 0; x < n; ++x)
        for (int y = 0; y < n; ++y)
            for (int z = 0; z < n; ++z) {
                const Vec3 c{float(x), float(y), float(z)};
                if (isSphere(x, y, z)) {
                    geometry.addSphere(Sphere{c, 0.1f}, 0);
                    continue;
                }
                const auto base = uint32_t(p.size());
                p.insert(p.end(), {c, c + Vec3(0.2f, 0.0f, 0.0f), c + Vec3(0.0f, 0.2f, 0.1f)});
                tris.push_back(glm::uvec3(base, base + 1, base + 2));
            }
    if (!tris.empty()) geometry.addTriangles(p, tris, 0);
}

TEST(KdTreeBuild, SameTreeOnEveryThreadCount) {
    // The bunny: 69,451 triangles, so some thirty subtrees are built as separate tasks.
    const TriangleMesh mesh =
        loadObj(std::string(CAUSTIC_DEFAULT_ASSETS_DIR) + "/stanford-bunny.obj", MeshTransform{},
                "/meshes/stanford-bunny.obj");
    Geometry geometry;
    geometry.addTriangles(mesh.positions, mesh.triangles, 0);
    // At least this many nodes: the default tree's leaves hold many blocks of eight triangles.
    const size_t minNodes[] = {1000, 100000};
    const std::vector<testing::KdTreeVariant> variants = testing::kdTreeVariants();
    ASSERT_EQ(variants.size(), std::size(minNodes));
    for (size_t v = 0; v < variants.size(); ++v) {
        const testing::KdTreeVariant& variant = variants[v];
        SCOPED_TRACE(variant.name);
        const int threads = omp_get_max_threads();
        omp_set_num_threads(1);
        const KdTreeAccel serial(geometry, variant.options);
        omp_set_num_threads(std::max(threads, 4));
        const KdTreeAccel parallel(geometry, variant.options);
        omp_set_num_threads(threads);
        EXPECT_GT(serial.nodes().size(), minNodes[v]);
        EXPECT_EQ(serial.stats().interiorNodes, parallel.stats().interiorNodes);
        EXPECT_EQ(serial.stats().sahCost, parallel.stats().sahCost);
        EXPECT_TRUE(treeBytes(serial) == treeBytes(parallel));
    }
}

// A leaf tests eight triangles at once but spheres one by one, and the SAH counts them so: the same
// grid of small shapes makes leaves of eight times as many triangles as spheres (16 spheres and
// 128 triangles on average with the default costs; counted alike, they would be the same size).
TEST(KdTreeBuild, LeavesHoldTrianglesByTheBlockAndSpheresOneByOne) {
    auto meanLeaf = [](const KdTreeAccel& tree) {
        const KdTreeStats& s = tree.stats();
        return double(s.references) / double(s.leaves - s.emptyLeaves);
    };
    Geometry spheres, triangles;
    addGrid(spheres, 16, [](int, int, int) { return true; });
    addGrid(triangles, 16, [](int, int, int) { return false; });
    const double sphereLeaf = meanLeaf(KdTreeAccel(spheres));
    const double triangleLeaf = meanLeaf(KdTreeAccel(triangles));
    EXPECT_GT(triangleLeaf, 4.0 * sphereLeaf)
        << sphereLeaf << " spheres, " << triangleLeaf << " triangles";
}

// A leaf's lane is tested as a triangle, from the vertices the leaf holds, unless its primitive
// word is marked as another kind (kd_leaf::kOtherKind): the mark must be exactly right, or a sphere
// is tested as a triangle of zero vertices, or a triangle through the geometry's records.
TEST(KdTreeBuild, MarksPrimitivesOtherThanTriangles) {
    Geometry geometry;
    addGrid(geometry, 8, [](int x, int y, int z) { return (x + y + z) % 3 == 0; });
    const KdTreeAccel tree(geometry);
    const std::span<const uint32_t> data = tree.leafData();
    std::vector<bool> seen(geometry.size(), false);
    for (const KdTreeAccel::Node& n : tree.nodes()) {
        if (!n.isLeaf()) continue;
        const uint32_t count = n.primCount();
        for (uint32_t k = 0; k < count; ++k) {
            const uint32_t word = data[n.leafOffset + kd_leaf::primitives(count) + k];
            const uint32_t prim = word & ~kd_leaf::kOtherKind;
            ASSERT_LT(prim, geometry.size());
            const bool other = (word & kd_leaf::kOtherKind) != 0;
            EXPECT_EQ(other, geometry.kind(prim) != PrimKind::Triangle) << "primitive " << prim;
            seen[prim] = true;
        }
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), true), std::ptrdiff_t(geometry.size()));
}

}  // namespace
}  // namespace caustic
