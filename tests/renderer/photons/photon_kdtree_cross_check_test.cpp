// Every kind of point cloud against brute force: the kd-tree's neighbours must equal brute
// force's exactly (see kdtree_clouds.h for the clouds, the queries and the checks).
#include <gtest/gtest.h>

#include "kdtree_clouds.h"

namespace caustic {
namespace {

using namespace kdtree_test;  // the clouds and checks of this test family

// ---- Against brute force.

TEST(PhotonKdTree, UniformCloudsMatchBruteForce) {
    // Sizes around the leaf size (8) and the first splits, and a large-ish cloud.
    for (size_t n : {0, 1, 2, 3, 7, 8, 9, 16, 17, 100, 10000})
        crossCheck("uniform", uniformCloud(n, -1.0f, 1.0f, uint32_t(100 + n)), uint32_t(n));
}

TEST(PhotonKdTree, LargeUniformCloudMatchesBruteForce) {
    // Above the parallel build threshold (2^15): the tree is built with OpenMP tasks. Brute force
    // costs O(n) a call (and unbounded ones sort the whole cloud), so: 200 queries, 8 random
    // (k, bound) pairs each, and one query with every pair, FLT_MAX and infinity included.
    CrossCheck check("uniform", uniformCloud(200000, -1.0f, 1.0f, 7));
    check.run(200, 1, 8, 8);
}

TEST(PhotonKdTree, ClusteredCloudsMatchBruteForce) {
    crossCheck("clusters apart", clusteredCloud(200, false, 11), 12);
    crossCheck("clusters nested", clusteredCloud(200, true, 13), 14);
    crossCheck("few clusters", clusteredCloud(3, false, 15), 16);
}

TEST(PhotonKdTree, DuplicatedPointsMatchBruteForce) {
    crossCheck("duplicates shuffled", duplicatedCloud(400, true, 21), 22);
    crossCheck("duplicates adjacent", duplicatedCloud(300, false, 23), 24);
    crossCheck("few duplicates", duplicatedCloud(3, true, 25), 26);

    // Radius 0 finds exactly the copies of the query point (distinct points of this cloud are at
    // least ~1e-7 apart, so no squared distance underflows to 0).
    CrossCheck check("duplicates", duplicatedCloud(200, true, 27));
    const Points& points = check.points();
    std::vector<Neighbor> out;
    for (size_t i = 0; i < points.size(); i += 37) {
        check.tree().withinRadius(points[i], 0.0f, out);
        std::vector<Neighbor> copies;
        for (size_t j = 0; j < points.size(); ++j)
            if (points[j] == points[i]) copies.push_back({0.0f, uint32_t(j)});
        EXPECT_EQ(out, copies) << "copies of point " << i;
        EXPECT_GE(out.size(), 2u);
    }
}

TEST(PhotonKdTree, AllIdenticalPointsAreOrderedByIndex) {
    const Vec3 c(0.3f, -0.7f, 2.5f), q(1.0f, 0.0f, 2.0f);
    for (size_t n : {1, 2, 8, 9, 100, 2000}) {
        CrossCheck check("identical", Points(n, c));
        // Every point ties: the k nearest are the first k indices, from anywhere.
        for (Vec3 p : {c, q}) {
            for (int k : {1, 2, 50, int(n), int(n) + 1}) {
                std::vector<Neighbor> out, expected;
                for (size_t i = 0; i < std::min(n, size_t(k)); ++i)
                    expected.push_back({distance2(c, p), uint32_t(i)});
                check.tree().nearest(p, k, kInf, out);
                EXPECT_EQ(out, expected) << n << " points, k " << k << ", query " << str(p);
            }
        }
        check.run(20, 20, 0, uint32_t(n));
    }
}

TEST(PhotonKdTree, PlanesLinesAndLatticesMatchBruteForce) {
    crossCheck("plane grid", planeCloud(3000, true, 31), 32);
    crossCheck("plane", planeCloud(3000, false, 33), 34);
    crossCheck("line x", lineCloud(2000, false, 35), 36);
    crossCheck("line diagonal", lineCloud(2000, true, 37), 38);
    crossCheck("integer lattice", latticeCloud(16, 1.0f, 39), 40);
    crossCheck("0.1 lattice", latticeCloud(12, 0.1f, 41), 42);
    crossCheck("small lattice", latticeCloud(3, 1.0f, 43), 44);
}

TEST(PhotonKdTree, HugeAndTinyCoordinatesMatchBruteForce) {
    // Squared distances up to ~1e37, still finite.
    crossCheck("huge 1e18", uniformCloud(3000, -1e18f, 1e18f, 51), 52);
    // Every coordinate magnitude from 1e-30 to 1e18 in one cloud.
    crossCheck("log scale", logScaleCloud(3000, 53), 54);
    // Squared distances ~1e-40: denormal, all below FLT_MIN. Denormal arithmetic is slow, and
    // every bound from FLT_MIN up admits the whole cloud: a smaller cloud.
    crossCheck("tiny 1e-20", uniformCloud(600, -1e-20f, 1e-20f, 55), 56, 40);
    // Squared distances ~1e-60 underflow to 0: every point ties with every other, though the
    // points (and so the splits) are distinct.
    crossCheck("tiny 1e-30", uniformCloud(1000, -1e-30f, 1e-30f, 57), 58, 40);
}

TEST(PhotonKdTree, OverflowingDistancesTieAtInfinity) {
    // Coordinates up to 1e30: the squared distance between distinct points overflows to infinity,
    // which only an infinite bound admits; then they tie, ordered by index.
    CrossCheck check("overflow 1e30", uniformCloud(2000, -1e30f, 1e30f, 61));
    const Points& points = check.points();
    std::vector<Neighbor> out;
    check.tree().nearest(Vec3(0.0f), 3, kInf, out);
    EXPECT_EQ(out, (std::vector<Neighbor>{{kInf, 0}, {kInf, 1}, {kInf, 2}}));
    check.tree().nearest(Vec3(0.0f), 3, kMaxFloat, out);
    EXPECT_TRUE(out.empty());
    check.tree().nearest(points[500], 3, kInf, out);
    EXPECT_EQ(out, (std::vector<Neighbor>{{0.0f, 500}, {kInf, 0}, {kInf, 1}}));
    check.tree().withinRadius(points[500], kMaxFloat, out);
    EXPECT_EQ(out, (std::vector<Neighbor>{{0.0f, 500}}));
    check.tree().withinRadius(Vec3(0.0f), kInf, out);
    EXPECT_EQ(out.size(), points.size());
    check.run(60, 60, 0, 62);
}

TEST(PhotonKdTree, NonFiniteQueriesAndArgumentsAgreeWithBruteForce) {
    // A NaN query point (or bound) compares false with every bound: both indexes find nothing.
    // A query at infinity is infinitely far from every point: an infinite bound admits them all,
    // in index order, and any finite bound none. A negative k finds nothing.
    CrossCheck check("non-finite", uniformCloud(1000, -1.0f, 1.0f, 71));
    struct Case {
        Vec3 p;
        int k;
        float bound;
        size_t expected;
    };
    const size_t n = check.points().size();
    const Case cases[] = {
        {Vec3(kNaN, 0.0f, 0.0f), 5, kInf, 0},
        {Vec3(0.0f, 0.0f, kNaN), 5, kInf, 0},
        {Vec3(kNaN), 5, kInf, 0},
        {Vec3(kNaN), -1, kInf, 0},
        {Vec3(0.0f), 5, kNaN, 0},
        {Vec3(0.0f), -1, kNaN, 0},
        {Vec3(0.0f), -3, kInf, 0},
        {Vec3(0.0f), std::numeric_limits<int>::min(), kInf, 0},
        {Vec3(0.0f), 5, -1.0f, 0},
        {Vec3(0.0f), -1, -1.0f, 0},
        {Vec3(kInf, 0.0f, 0.0f), 5, kInf, 5},
        {Vec3(0.0f, -kInf, 0.0f), 5, kInf, 5},
        {Vec3(kInf, -kInf, kInf), 5, kInf, 5},
        {Vec3(kInf, 0.0f, 0.0f), -1, kInf, n},
        {Vec3(kInf, 0.0f, 0.0f), 5, kMaxFloat, 0},
        {Vec3(kInf, 0.0f, 0.0f), -1, kMaxFloat, 0},
    };
    std::vector<float> d2(n);
    for (size_t i = 0; i < std::size(cases); ++i) {
        const Case& c = cases[i];
        for (size_t j = 0; j < n; ++j) d2[j] = distance2(check.points()[j], c.p);
        // withinRadius is k = -1 in check(); a negative k for nearest is called directly.
        if (c.k < -1) {
            std::vector<Neighbor> t, b;
            check.tree().nearest(c.p, c.k, c.bound, t);
            check.brute().nearest(c.p, c.k, c.bound, b);
            EXPECT_EQ(t, b) << "case " << i;
            EXPECT_TRUE(t.empty()) << "case " << i;
            continue;
        }
        check.check({c.p, "non-finite"}, i, c.k, c.bound, d2);
        std::vector<Neighbor> out;
        if (c.k < 0) {
            check.tree().withinRadius(c.p, c.bound, out);
        } else {
            check.tree().nearest(c.p, c.k, c.bound, out);
        }
        EXPECT_EQ(out.size(), c.expected) << "case " << i << ", query " << str(c.p);
        for (size_t j = 0; j < out.size(); ++j)
            EXPECT_EQ(out[j], (Neighbor{kInf, uint32_t(j)})) << "case " << i;
    }
}

}  // namespace
}  // namespace caustic
