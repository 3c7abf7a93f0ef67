// The kd-tree's build splits the top of the tree among OpenMP tasks; whatever thread builds which
// subtree, the tree must be the same, so that renders are bit-identical on any thread count.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cstring>

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

TEST(KdTreeBuild, SameTreeOnEveryThreadCount) {
    // The bunny: 69,451 triangles, so some thirty subtrees are built as separate tasks.
    const TriangleMesh mesh =
        loadObj(std::string(CAUSTIC_DEFAULT_ASSETS_DIR) + "/stanford-bunny.obj", MeshTransform{},
                "/meshes/stanford-bunny.obj");
    Geometry geometry;
    geometry.addTriangles(mesh.positions, mesh.triangles, 0);
    for (const testing::KdTreeVariant& variant : testing::kdTreeVariants()) {
        SCOPED_TRACE(variant.name);
        const int threads = omp_get_max_threads();
        omp_set_num_threads(1);
        const KdTreeAccel serial(geometry, variant.options);
        omp_set_num_threads(std::max(threads, 4));
        const KdTreeAccel parallel(geometry, variant.options);
        omp_set_num_threads(threads);
        EXPECT_GT(serial.nodes().size(), 10000u);
        EXPECT_EQ(serial.stats().interiorNodes, parallel.stats().interiorNodes);
        EXPECT_EQ(serial.stats().sahCost, parallel.stats().sahCost);
        EXPECT_TRUE(treeBytes(serial) == treeBytes(parallel));
    }
}

}  // namespace
}  // namespace caustic
