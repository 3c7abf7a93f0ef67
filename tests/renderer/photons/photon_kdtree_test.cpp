// The photon kd-tree must return exactly what brute force returns: the same neighbours, the same
// squared distances to the bit, in the same order, for every query. Neighbours are ordered by
// (dist2, id), so the answer is unique even among duplicated points and exact ties: any difference
// is a bug, there is no tolerance. The clouds aim at what breaks kd-trees: exact ties in split
// coordinates (duplicates, planes, lines, lattices), ties in distance (lattice midpoints), a search
// bound equal to some point's distance, scales from denormal to overflowing squared distances, and
// counts around the leaf size (8). Besides agreeing with brute force, every kd-tree answer is
// checked on its own: sorted, no id twice, dist2 recomputed, and min(k, #points within the bound)
// neighbours.
#include <gtest/gtest.h>
#include <omp.h>

#include "kdtree_clouds.h"

namespace caustic {
namespace {

using namespace kdtree_test;  // the clouds and checks of this test family

// ---- Hand-checked answers.

TEST(NeighborIndex, BruteForceReferenceGivesTheHandComputedAnswer) {
    // The reference everything else is compared with: dist2 from the origin 0, 1, 4, 1, 1 and
    // ties ordered by index.
    Points points = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {1, 0, 0}, {0, 0, -1}};
    BruteForceNeighbors brute(points);
    PhotonKdTree tree(points);
    using V = std::vector<Neighbor>;
    V out;
    for (const NeighborIndex* index :
         {static_cast<const NeighborIndex*>(&brute), static_cast<const NeighborIndex*>(&tree)}) {
        index->withinRadius(Vec3(0.0f), 1.0f, out);
        EXPECT_EQ(out, (V{{0, 0}, {1, 1}, {1, 3}, {1, 4}}));
        index->nearest(Vec3(0.0f), 3, kInf, out);
        EXPECT_EQ(out, (V{{0, 0}, {1, 1}, {1, 3}}));
        index->nearest(Vec3(0.0f), 10, 0.5f, out);
        EXPECT_EQ(out, (V{{0, 0}}));
        index->nearest(Vec3(0.0f, 2.0f, 0.0f), 2, kInf, out);
        EXPECT_EQ(out, (V{{0, 2}, {4, 0}}));
        EXPECT_EQ(index->size(), 5u);
    }
}

TEST(NeighborIndex, OrderIsByDistanceThenIndex) {
    EXPECT_TRUE((Neighbor{1.0f, 7}) < (Neighbor{2.0f, 3}));
    EXPECT_TRUE((Neighbor{1.0f, 3}) < (Neighbor{1.0f, 7}));
    EXPECT_FALSE((Neighbor{1.0f, 7}) < (Neighbor{1.0f, 7}));
    EXPECT_TRUE((Neighbor{0.0f, 7}) == (Neighbor{-0.0f, 7}));
}

TEST(PhotonKdTree, EmptyMapFindsNothing) {
    PhotonKdTree tree(Points{});
    EXPECT_EQ(tree.size(), 0u);
    EXPECT_EQ(tree.depth(), 0);
    EXPECT_EQ(tree.memoryBytes(), 0u);
    std::vector<Neighbor> out = {{1.0f, 1}};  // cleared by every call
    tree.nearest(Vec3(0.0f), 5, kInf, out);
    EXPECT_TRUE(out.empty());
    out = {{1.0f, 1}};
    tree.withinRadius(Vec3(0.0f), kInf, out);
    EXPECT_TRUE(out.empty());
    crossCheck("empty", {}, 1);
}

TEST(PhotonKdTree, OnePointMap) {
    using V = std::vector<Neighbor>;
    PhotonKdTree tree(Points{{1, 2, 3}});
    EXPECT_EQ(tree.depth(), 0);
    V out;
    tree.nearest(Vec3(1, 2, 3), 1, 0.0f, out);
    EXPECT_EQ(out, (V{{0, 0}}));
    tree.nearest(Vec3(1, 2, 4), 5, kInf, out);
    EXPECT_EQ(out, (V{{1, 0}}));
    tree.nearest(Vec3(1, 2, 4), 5, 1.0f, out);  // the bound is inclusive
    EXPECT_EQ(out, (V{{1, 0}}));
    tree.nearest(Vec3(1, 2, 4), 5, std::nextafter(1.0f, 0.0f), out);
    EXPECT_EQ(out, V{});
    tree.nearest(Vec3(1, 2, 4), 0, kInf, out);
    EXPECT_EQ(out, V{});
    tree.withinRadius(Vec3(1, 2, 3), 0.0f, out);
    EXPECT_EQ(out, (V{{0, 0}}));
    tree.withinRadius(Vec3(1, 2, 4), 0.0f, out);
    EXPECT_EQ(out, V{});
    crossCheck("one point", Points{{1, 2, 3}}, 2);
}

// ---- Properties of the tree itself.

TEST(PhotonKdTree, ParallelQueriesMatchSerial) {
    // One tree, many threads (more than cores, to interleave them): the answers must not depend
    // on which thread asked or when.
    PhotonKdTree tree(clusteredCloud(300, false, 81));
    std::mt19937 rng(82);
    std::uniform_real_distribution<float> coordinate(-1000.0f, 1000.0f), exponent(-12.0f, 4.0f);
    std::vector<Vec3> ps(6000);
    std::vector<float> radii2(ps.size());
    for (size_t i = 0; i < ps.size(); ++i) {
        ps[i] = Vec3{coordinate(rng), coordinate(rng), coordinate(rng)};
        radii2[i] = std::pow(10.0f, exponent(rng));
    }
    auto query = [&](size_t i, std::vector<Neighbor>& nearest, std::vector<Neighbor>& within) {
        tree.nearest(ps[i], 1 + int(i % 64), i % 3 == 0 ? kInf : radii2[i] * 1e4f, nearest);
        tree.withinRadius(ps[i], radii2[i], within);
    };
    std::vector<std::vector<Neighbor>> serialNearest(ps.size()), serialWithin(ps.size());
    for (size_t i = 0; i < ps.size(); ++i) query(i, serialNearest[i], serialWithin[i]);
    std::vector<std::vector<Neighbor>> parallelNearest(ps.size()), parallelWithin(ps.size());
    const int threads = std::max(4, omp_get_max_threads());
#pragma omp parallel for schedule(dynamic, 8) num_threads(threads)
    for (size_t i = 0; i < ps.size(); ++i) query(i, parallelNearest[i], parallelWithin[i]);
    size_t mismatches = 0, found = 0;
    for (size_t i = 0; i < ps.size(); ++i) {
        mismatches +=
            parallelNearest[i] != serialNearest[i] || parallelWithin[i] != serialWithin[i];
        found += serialWithin[i].size();
    }
    EXPECT_EQ(mismatches, 0u);
    EXPECT_GT(found, 0u);  // the radii are not all too small to find anything
}

// The levels of the median-split recursion, computed directly: a range of more than a leaf's
// points splits into n / 2 and n - n / 2.
int splitDepth(size_t n) {
    return n <= PhotonKdTree::kLeafSize ? 0
                                        : 1 + std::max(splitDepth(n / 2), splitDepth(n - n / 2));
}

TEST(PhotonKdTree, MemoryIsSixteenBytesPerPointAndTheSplits) {
    // A position and an index per point, one split (8 bytes) per inner range of a complete tree
    // of the depth, and a leaf's padding; nothing for an empty map.
    constexpr size_t kPadding = 2 * (PhotonKdTree::kLeafSize - 1) * sizeof(float);
    EXPECT_EQ(PhotonKdTree(Points{}).memoryBytes(), 0u);
    for (size_t n : {1, 7, 8, 9, 16, 17, 100, 10000, 40000}) {
        Points points = uniformCloud(n, -1.0f, 1.0f, uint32_t(n));
        PhotonKdTree tree(points);
        EXPECT_EQ(tree.size(), n);
        const size_t splits = (size_t(1) << splitDepth(n)) - 1;
        EXPECT_EQ(tree.memoryBytes(), 16 * n + 8 * splits + kPadding) << n << " points";
        EXPECT_LE(8 * splits, 16 * n) << n << " points";
        EXPECT_EQ(BruteForceNeighbors(points).memoryBytes(), sizeof(Vec3) * n) << n << " points";
    }
}

TEST(PhotonKdTree, DepthIsTheSplitLevelsOverLeavesOfAtMostLeafSize) {
    std::vector<size_t> sizes;
    for (size_t n = 0; n <= 300; ++n) sizes.push_back(n);
    for (size_t n : {511, 512, 513, 1023, 1024, 1025, 65535, 65536, 65537}) sizes.push_back(n);
    Points all = uniformCloud(65537, -1.0f, 1.0f, 91);
    for (size_t n : sizes) {
        PhotonKdTree tree(Points(all.begin(), all.begin() + ptrdiff_t(n)));
        // Leaves of at most kLeafSize points: ceil(log2(ceil(n / kLeafSize))) levels.
        const size_t leaves = (n + PhotonKdTree::kLeafSize - 1) / PhotonKdTree::kLeafSize;
        const int expected = leaves <= 1 ? 0 : int(std::ceil(std::log2(double(leaves))));
        EXPECT_EQ(tree.depth(), expected) << n << " points";
        EXPECT_EQ(tree.depth(), splitDepth(n)) << n << " points";
    }
}

}  // namespace
}  // namespace caustic
