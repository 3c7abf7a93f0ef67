// Meshes with vertex normals: the interpolated shading normal, the point lifted onto the smooth
// surface (Hanika 2021), and what that does at the shadow terminator of a coarse sphere.
#include <gtest/gtest.h>

#include <sstream>

#include "accel/accelerator.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "geometry/geometry.h"
#include "scene/mesh_loader.h"

namespace caustic {
namespace {

// A UV sphere of radius 1 with `rings` x `segments` quads (two triangles each, counter-clockwise
// seen from outside) and its exact normals at the vertices.
void uvSphere(int rings, int segments, std::vector<Vec3>& positions,
              std::vector<glm::uvec3>& triangles, std::vector<Vec3>& normals) {
    for (int r = 0; r <= rings; ++r)
        for (int s = 0; s <= segments; ++s) {
            const float theta = kPi * float(r) / float(rings);
            const float phi = 2.0f * kPi * float(s) / float(segments);
            const Vec3 p(std::sin(theta) * std::cos(phi), std::cos(theta),
                         std::sin(theta) * std::sin(phi));
            positions.push_back(p);
            normals.push_back(p);
        }
    auto at = [&](int r, int s) { return uint32_t(r * (segments + 1) + s); };
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            if (r > 0) triangles.emplace_back(at(r, s), at(r, s + 1), at(r + 1, s));
            if (r + 1 < rings) triangles.emplace_back(at(r, s + 1), at(r + 1, s + 1), at(r + 1, s));
        }
}

TEST(ShadingNormals, InterpolatedOnNsSideAndFlatWithout) {
    Geometry g;
    const std::vector<Vec3> p{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    // Normals tilted, and given on the back of the winding: the shading normal joins n's side.
    const std::vector<Vec3> vn{glm::normalize(Vec3(-1, 0, -1)), glm::normalize(Vec3(0, -1, -1)),
                               Vec3(0, 0, -1)};
    g.addTriangles(p, {glm::uvec3(0, 1, 2)}, 0, vn);
    g.addTriangles(p, {glm::uvec3(0, 1, 2)}, 0);  // no normals: flat
    for (uint32_t prim : {0u, 1u}) {
        const Ray ray{Vec3(0.25f, 0.25f, 1.0f), Vec3(0, 0, -1)};
        auto h = g.intersect(prim, ray, kInfinity);
        ASSERT_TRUE(h);
        const SurfaceInteraction si = g.interaction(ray, g.finish(prim, ray, *h));
        EXPECT_EQ(si.n, Vec3(0, 0, 1));
        if (prim == 1) {
            EXPECT_EQ(si.ns, si.n);
            EXPECT_EQ(si.pShading, si.p);
            continue;
        }
        const Vec3 expected = -glm::normalize(0.5f * vn[0] + 0.25f * vn[1] + 0.25f * vn[2]);
        EXPECT_NEAR(glm::length(si.ns - expected), 0.0f, 1e-6f);
    }
}

TEST(ShadingNormals, ObjNormalsAreReadAndTransformed) {
    std::istringstream obj(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 1 0 1\nvn 0 0 1\nf 1//2 2//2 3//1\nf 1//1 3//1 2//2\n");
    MeshTransform t;
    t.scale = Vec3(2.0f, 1.0f, 1.0f);
    const TriangleMesh mesh = parseObj(obj, "n.obj", t, "/shapes/0/file");
    // Vertices are the distinct (position, normal) pairs: (1,2) (2,2) (3,1) (1,1).
    ASSERT_EQ(mesh.positions.size(), 4u);
    ASSERT_EQ(mesh.normals.size(), 4u);
    EXPECT_TRUE(mesh.texcoords.empty());
    // Normals transform by the inverse transpose: x is divided by the scale 2.
    const Vec3 n1 = glm::normalize(Vec3(0.5f, 0, 1)), n2(0, 0, 1);
    // Each face's corners, whatever order triangulation starts them in: position -> normal.
    const std::vector<std::vector<std::pair<Vec3, Vec3>>> faces{
        {{Vec3(0, 0, 0), n2}, {Vec3(2, 0, 0), n2}, {Vec3(0, 1, 0), n1}},
        {{Vec3(0, 0, 0), n1}, {Vec3(0, 1, 0), n1}, {Vec3(2, 0, 0), n2}}};
    ASSERT_EQ(mesh.triangles.size(), 2u);
    for (size_t f = 0; f < 2; ++f)
        for (int corner = 0; corner < 3; ++corner) {
            const uint32_t v = mesh.triangles[f][corner];
            bool found = false;
            for (const auto& [position, normal] : faces[f])
                found = found || (mesh.positions[v] == position &&
                                  glm::length(mesh.normals[v] - normal) < 1e-6f);
            EXPECT_TRUE(found) << "face " << f << " corner " << corner;
        }
}

// A coarse sphere (8 x 12 quads) lit from the side: where the smooth surface faces the light, its
// flat triangles must not shadow themselves. From the hit point, shadow rays towards the light are
// blocked by the neighbouring face at many such points; from the lifted point, at almost none.
TEST(ShadingNormals, LiftedOriginsClearTheShadowTerminator) {
    std::vector<Vec3> positions, normals;
    std::vector<glm::uvec3> triangles;
    uvSphere(8, 12, positions, triangles, normals);
    Geometry g;
    g.addTriangles(positions, triangles, 0, normals);
    auto accel = createAccelerator("embree", g);
    const Vec3 light = glm::normalize(Vec3(1.0f, 0.3f, 0.2f));
    Rng rng(5);
    int lit = 0, blockedFromHit = 0, blockedFromLifted = 0;
    for (int i = 0; i < 20000; ++i) {
        // A ray from outside towards a random point of the sphere.
        const Vec3 target = 0.95f * sampleUniformSphere(rng.uniform2());
        const Vec3 origin = target + 3.0f * glm::normalize(target);
        const Ray ray{origin, glm::normalize(target - origin)};
        auto hit = accel->intersect(ray, kInfinity);
        if (!hit) continue;
        const SurfaceInteraction si = g.interaction(ray, *hit);
        if (!(glm::dot(si.ns, light) > 0.1f)) continue;
        ++lit;
        blockedFromHit +=
            accel->occluded(Ray{offsetRayOrigin(si.p, si.pError, si.n, light), light}, kInfinity);
        blockedFromLifted += accel->occluded(Ray{rayOrigin(si, light), light}, kInfinity);
    }
    std::printf(
        "coarse sphere, %d points lit by the shading normal: shadowed from the hit point "
        "%d, from the lifted point %d\n",
        lit, blockedFromHit, blockedFromLifted);
    ASSERT_GT(lit, 5000);
    EXPECT_GT(blockedFromHit, lit / 100);
    EXPECT_LE(blockedFromLifted, lit / 1000);
}

}  // namespace
}  // namespace caustic
