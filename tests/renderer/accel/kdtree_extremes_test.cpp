// The kd-tree at its edges, each case once undefined behaviour that the sanitizer build reports.
// Scenes whose extent overflows float: a sphere of radius 3e38 beside a mesh of more than 64
// triangles (so the root is split by binned SAH) cast NaN to int in the binning (issue 12, bug 2)
// and, with the SAH cost NaN, left every primitive in one leaf. Any finite scene must build and
// agree with brute force. And a tree whose leaves are empty or hold one primitive each.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "accel/bruteforce.h"
#include "accel/kdtree/kdtree.h"
#include "renderer/accel/kdtree_variants.h"
#include "renderer/accel/ray_sets.h"
#include "scene/mesh_loader.h"
#include "support/accel_agreement.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

// The teapot (6320 triangles) inside or beside a huge sphere; the camera looks at the teapot.
Json hugeSphereScene(double center, double radius) {
    Json doc = Json::parse(R"({
        "camera": {"position": [0, 2, 8], "look_at": [0, 1, 0]},
        "materials": {"white": {"type": "diffuse"}},
        "shapes": [{"type": "mesh", "file": "teapot.obj", "material": "white"}],
        "settings": {"accelerator": "kdtree"}
    })");
    doc["shapes"].push_back({{"type", "sphere"},
                             {"center", {center, 0.0, 0.0}},
                             {"radius", radius},
                             {"material", "white"}});
    return doc;
}

// Builds each kd-tree variant and checks it against brute force on rays around the mesh (the
// sphere's bounds would spread random rays over 1e38) and on the camera's rays.
void expectKdTreeMatchesBruteForce(const Json& doc) {
    std::unique_ptr<Scene> scene = testing::sceneFromJson(doc);
    const Geometry& g = scene->geometry;
    BruteForceAccel brute(g);
    Bounds3 mesh;
    for (uint32_t prim = 0; prim + 1 < g.size(); ++prim) mesh.extend(g.bounds(prim));
    Rng rng(12);
    std::vector<Ray> rays;
    testing::addRandomRays(mesh, 2000, rng, rays);
    testing::addAxisAlignedRays(mesh, 500, rng, rays);
    testing::addVertexAndEdgeRays(g, mesh, 500, rng, rays);
    const Camera& camera = scene->camera;
    for (int y = 0; y < camera.height(); y += 32)
        for (int x = 0; x < camera.width(); x += 32)
            rays.push_back(camera.generateRay(float(x) + 0.5f, float(y) + 0.5f));

    for (const testing::KdTreeVariant& variant : testing::kdTreeVariants()) {
        SCOPED_TRACE(variant.name);
        KdTreeAccel kdtree(g, variant.options);
        const KdTreeStats& stats = kdtree.stats();
        EXPECT_GT(stats.interiorNodes, 0u) << "the SAH found no split: every primitive in one leaf";
        EXPECT_TRUE(std::isfinite(stats.sahCost)) << stats.sahCost;
        EXPECT_TRUE(isFinite(kdtree.bounds().lo) && isFinite(kdtree.bounds().hi));
        EXPECT_EQ(testing::firstDisagreement(kdtree, brute, rays), std::nullopt);
    }
}

TEST(KdTreeExtremes, SphereOfRadius3e38BesideAMesh) {
    // The sphere's box spans 6e38: its extent and area overflow float.
    expectKdTreeMatchesBruteForce(hugeSphereScene(0.0, 3e38));
}

TEST(KdTreeExtremes, SphereReachingPastTheLargestFloat) {
    // Its box reaches 6e38 on one side, which float holds only as infinity.
    expectKdTreeMatchesBruteForce(hugeSphereScene(3e38, 3e38));
}

// Found by tests/fuzz/obj_fuzzer (minimized): a segment (a triangle of no area) on the x axis and a
// triangle give a tree of an empty leaf and one-primitive leaves, so the leaves' index array is
// empty: entering the empty leaf must not take &primIndices_[0] of it.
TEST(KdTreeExtremes, EmptyLeafBesideOnePrimitiveLeaves) {
    std::istringstream obj("v 0 0 0\nv 2 0 0\nv -1 0 0\nv -5 0 0\nv 0 7 9\nf 2 1 2\nf 3 4 5\n");
    TriangleMesh mesh = parseObj(obj, "empty-leaf.obj", MeshTransform{}, "/file");
    Geometry g;
    g.addTriangles(mesh.positions, mesh.triangles, 0);
    // The finest tree has that shape; the default one puts both primitives in one leaf.
    KdTreeAccel kdtree(g, testing::kdTreeVariants().back().options);
    BruteForceAccel brute(g);
    const KdTreeStats& stats = kdtree.stats();
    ASSERT_GT(stats.emptyLeaves, 0u);
    ASSERT_EQ(stats.references, stats.leaves - stats.emptyLeaves) << "a leaf holds two";

    // Through every leaf.
    Rng rng(13);
    std::vector<Ray> rays;
    testing::addRandomRays(g.bounds(), 2000, rng, rays);
    testing::addAxisAlignedRays(g.bounds(), 1000, rng, rays);
    EXPECT_EQ(testing::firstDisagreement(kdtree, brute, rays), std::nullopt);
}

}  // namespace
}  // namespace caustic
