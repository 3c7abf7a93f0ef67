// The kd-tree over scenes whose extent overflows float: a sphere of radius 3e38 beside a mesh of
// more than 64 triangles (so the root is split by binned SAH) once cast NaN to int in the binning
// (issue 12, bug 2; undefined behaviour, which the sanitizer build reports) and, with the SAH cost
// NaN, left every primitive in one leaf. Any finite scene must build and agree with brute force.
#include <gtest/gtest.h>

#include <cmath>

#include "accel/bruteforce.h"
#include "accel/kdtree/kdtree.h"
#include "renderer/accel/ray_sets.h"
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

// Builds the kd-tree and checks it against brute force on rays around the mesh (the sphere's
// bounds would spread random rays over 1e38) and on the camera's rays.
void expectKdTreeMatchesBruteForce(const Json& doc) {
    std::unique_ptr<Scene> scene = testing::sceneFromJson(doc);
    const Geometry& g = scene->geometry;
    KdTreeAccel kdtree(g);
    BruteForceAccel brute(g);

    const KdTreeStats& stats = kdtree.stats();
    EXPECT_GT(stats.interiorNodes, 0u) << "the SAH found no split: every primitive in one leaf";
    EXPECT_TRUE(std::isfinite(stats.sahCost)) << stats.sahCost;
    EXPECT_TRUE(isFinite(kdtree.bounds().lo) && isFinite(kdtree.bounds().hi));

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
    EXPECT_EQ(testing::firstDisagreement(kdtree, brute, rays), std::nullopt);
}

TEST(KdTreeExtremes, SphereOfRadius3e38BesideAMesh) {
    // The sphere's box spans 6e38: its extent and area overflow float.
    expectKdTreeMatchesBruteForce(hugeSphereScene(0.0, 3e38));
}

TEST(KdTreeExtremes, SphereReachingPastTheLargestFloat) {
    // Its box reaches 6e38 on one side, which float holds only as infinity.
    expectKdTreeMatchesBruteForce(hugeSphereScene(3e38, 3e38));
}

}  // namespace
}  // namespace caustic
