#include "geometry/geometry.h"

#include <gtest/gtest.h>

#include <limits>

#include "accel/bruteforce.h"
#include "core/rng.h"
#include "core/sampling.h"

namespace caustic {

TEST(Sphere, HitsFromOutsideAndInside) {
    Sphere s{Vec3(0, 0, -5), 1.0f};
    auto outside = s.intersect(Ray{Vec3(0), Vec3(0, 0, -1)}, kInfinity);
    ASSERT_TRUE(outside);
    EXPECT_FLOAT_EQ(*outside, 4.0f);
    auto inside = s.intersect(Ray{Vec3(0, 0, -5), Vec3(1, 0, 0)}, kInfinity);
    ASSERT_TRUE(inside);
    EXPECT_FLOAT_EQ(*inside, 1.0f);
    EXPECT_FALSE(s.intersect(Ray{Vec3(0), Vec3(0, 0, 1)}, kInfinity));
    EXPECT_FALSE(s.intersect(Ray{Vec3(0), Vec3(0, 0, -1)}, 3.9f));
}

TEST(Sphere, SmallSphereFarAwayKeepsItsPrecision) {
    // Ray Tracing Gems ch. 7: the naive discriminant loses a tiny, distant sphere.
    Sphere s{Vec3(0, 0, -1e4f), 1e-2f};
    auto hit = s.intersect(Ray{Vec3(0), Vec3(0, 0, -1)}, kInfinity);
    ASSERT_TRUE(hit);
    EXPECT_NEAR(*hit, 1e4f - 1e-2f, 1e-3f);
}

TEST(Quad, FrontFacesCrossOfEdgesAndUvSpansTheUnitSquare) {
    Geometry g;
    g.addQuad(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0), 0);
    BruteForceAccel accel(g);
    Rng rng(1);
    for (int i = 0; i < 1000; ++i) {
        Vec2 st = rng.uniform2();
        Vec3 target(2 * st.x, st.y, 0);
        Ray ray{Vec3(0.3f, 0.2f, 3), glm::normalize(target - Vec3(0.3f, 0.2f, 3))};
        auto hit = accel.intersect(ray, kInfinity);
        ASSERT_TRUE(hit);
        EXPECT_NEAR(hit->uv.x, st.x, 1e-5f);
        EXPECT_NEAR(hit->uv.y, st.y, 1e-5f);
        EXPECT_EQ(hit->n, Vec3(0, 0, 1));
        SurfaceInteraction si = g.interaction(ray, *hit);
        EXPECT_NEAR(glm::length(si.p - target), 0.0f, 1e-5f);
    }
}

TEST(Triangle, RaysThroughASharedEdgeNeverSlipThrough) {
    // Two triangles sharing the diagonal of the unit square; rays aimed exactly at the diagonal.
    Geometry g;
    g.addTriangles({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)},
                   {glm::uvec3(0, 1, 2), glm::uvec3(0, 2, 3)}, 0);
    Rng rng(3);
    int misses = 0;
    for (int i = 0; i < 10000; ++i) {
        float s = rng.uniform();
        Vec3 o(rng.uniform() * 4 - 2, rng.uniform() * 4 - 2, 1 + rng.uniform());
        Ray ray{o, glm::normalize(Vec3(s, s, 0) - o)};
        int hits = 0;
        for (uint32_t prim = 0; prim < g.size(); ++prim)
            hits += g.intersect(prim, ray, kInfinity) ? 1 : 0;
        if (hits == 0) ++misses;
    }
    EXPECT_EQ(misses, 0);  // watertight: no ray slips through the crack
}

TEST(Triangle, ZeroAreaTrianglesAreNeverHit) {
    Geometry g;
    g.addTriangles({Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(2, 2, 0)}, {glm::uvec3(0, 1, 2)}, 0);
    EXPECT_FALSE(g.intersect(0, Ray{Vec3(1, 1, 1), Vec3(0, 0, -1)}, kInfinity));
}

// Found by tests/fuzz/obj_fuzzer (tests/fuzz/obj/underflow-sliver.obj): a triangle one vertex of
// which sits 1.4e-45 (the least float) off the plane z = 0. A ray in that plane, beside the
// triangle, saw its edge functions underflow to (0, 0, 2.8e-45) in float and hit it; in double they
// are (-7e-46, 0, 2.1e-45): outside. The kd-tree, culling by boxes, rightly missed.
TEST(Triangle, EdgeFunctionsThatUnderflowAreDecidedInDouble) {
    Geometry g;
    const float least = std::numeric_limits<float>::denorm_min();
    g.addTriangles({Vec3(-1, 0.5f, 0), Vec3(0, 1, least), Vec3(0, 0, 0)}, {glm::uvec3(0, 1, 2)}, 0);
    EXPECT_FALSE(g.intersect(0, Ray{Vec3(0.5f, 0.5f, 0), Vec3(0, -1, 0)}, kInfinity));
    // Rays through its vertex and inside it, also in the plane, still hit.
    EXPECT_TRUE(g.intersect(0, Ray{Vec3(0, 0.5f, 0), Vec3(0, -1, 0)}, kInfinity));
    EXPECT_TRUE(g.intersect(0, Ray{Vec3(-0.25f, 0.5f, 0), Vec3(0, -1, 0)}, kInfinity));
}

// Found by fuzz_obj: a ray in the plane of a triangle (to within rounding) through its vertex
// (1, 0, 0), at t = 2.5. The projected triangle is a sliver, its edge functions are decided in
// double, and t from the plane, which such a ray meets anywhere, would be 1.53, outside the
// triangle and its box, where the kd-tree never looks. t is the blend of the vertices' depths.
TEST(Triangle, ARayInItsPlaneHitsInsideIt) {
    Geometry g;
    g.addTriangles({Vec3(0, 0, 0), Vec3(0, 1, 1e-4f), Vec3(1, 0, 0)}, {glm::uvec3(0, 1, 2)}, 0);
    Ray ray{Vec3(3, 1.5f, 0.000149999993f), Vec3(-0.800000012f, -0.600000024f, -5.99999985e-05f)};
    auto h = g.intersect(0, ray, kInfinity);
    ASSERT_TRUE(h);
    EXPECT_NEAR(h->t, 2.5f, 1e-6f);
}

// Also found by fuzz_obj: a ray in the plane z = 0 through the vertex (0, 0, 0) of a triangle
// tilted 1e-43 out of that plane, which straddles the ray's origin in depth. The plane's t is
// 0.63, a point outside the triangle; a hit may only be at the vertex (t = 0.7071).
TEST(Triangle, ARayInItsPlaneThroughAVertexHitsNowhereElse) {
    Geometry g;
    g.addTriangles({Vec3(0, 0, 0), Vec3(0, 1, 9.9492191e-44f), Vec3(-1, 0, 0)},
                   {glm::uvec3(0, 1, 2)}, 0);
    Ray ray{Vec3(0.5f, 0.5f, 5.04467447e-44f),
            Vec3(-0.707106769f, -0.707106769f, -7.14662217e-44f)};
    if (auto h = g.intersect(0, ray, kInfinity)) {
        EXPECT_NEAR(h->t, 0.70710678f, 1e-6f);
    }
}

TEST(Geometry, UniformSamplesLieOnTheSurfaceWithDensityOneOverArea) {
    Geometry g;
    g.addSphere(Sphere{Vec3(1, 2, 3), 0.5f}, 0);
    g.addQuad(Vec3(0), Vec3(2, 0, 0), Vec3(0, 0, 3), 0);
    g.addTriangles({Vec3(0), Vec3(4, 0, 0), Vec3(0, 2, 0)}, {glm::uvec3(0, 1, 2)}, 0);
    EXPECT_FLOAT_EQ(g.area(0), 4 * kPi * 0.25f);
    EXPECT_FLOAT_EQ(g.area(1), 6.0f);
    EXPECT_FLOAT_EQ(g.area(2), 4.0f);
    Rng rng(9);
    for (uint32_t prim = 0; prim < 3; ++prim) {
        for (int i = 0; i < 1000; ++i) {
            SurfaceSample s = g.sample(prim, rng.uniform2());
            EXPECT_FLOAT_EQ(s.pdfArea, 1.0f / g.area(prim));
            EXPECT_NEAR(glm::length(s.n), 1.0f, 1e-6f);
            // The point is on the primitive: a ray from just off the surface along -n hits it
            // there.
            Ray ray{s.p + 1e-3f * s.n, -s.n};
            auto h = g.intersect(prim, ray, kInfinity);
            ASSERT_TRUE(h) << "prim " << prim;
            EXPECT_NEAR(h->t, 1e-3f, 1e-4f);
        }
    }
}

TEST(RayOffset, SpawnedRaysDoNotReHitTheirSurfaceAtAnyScale) {
    Rng rng(5);
    for (float scale : {1e-4f, 1.0f, 1e4f}) {
        for (float shift : {0.0f, 1e5f}) {
            Geometry g;
            Vec3 c(shift);
            g.addSphere(Sphere{c, scale}, 0);
            g.addTriangles({c + scale * Vec3(-1, -1, 2), c + scale * Vec3(1, -1, 2),
                            c + scale * Vec3(0, 1, 2)},
                           {glm::uvec3(0, 1, 2)}, 0);
            BruteForceAccel accel(g);
            int selfHits = 0;
            for (int i = 0; i < 2000; ++i) {
                Vec3 dir = sampleUniformSphere(rng.uniform2());
                Ray ray{c, dir};
                auto hit = accel.intersect(ray, kInfinity);
                ASSERT_TRUE(hit);
                SurfaceInteraction si = g.interaction(ray, *hit);
                // Leave the sphere outwards in a random direction of the outer hemisphere.
                Vec3 w = sampleUniformSphere(rng.uniform2());
                if (glm::dot(w, si.n) < 0) w = -w;
                Ray out{offsetRayOrigin(si.p, si.pError, si.n, w), w};
                auto again = g.intersect(hit->prim, out, kInfinity);
                if (hit->prim == 0 && again) ++selfHits;
            }
            EXPECT_EQ(selfHits, 0) << "scale " << scale << " shift " << shift;
        }
    }
}

}  // namespace caustic
