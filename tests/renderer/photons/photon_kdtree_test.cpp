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

#include <algorithm>
#include <bit>
#include <cmath>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include "core/bounds.h"
#include "photons/brute_force_neighbors.h"
#include "photons/photon_kdtree.h"

namespace caustic {

// gtest prints neighbours in failure messages with this; 9 digits round-trip a float.
inline void PrintTo(const Neighbor& n, std::ostream* os) {
    *os << "{id " << n.id << ", dist2 " << std::setprecision(9) << n.dist2 << "}";
}

namespace {

using Points = std::vector<Vec3>;

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kMaxFloat = std::numeric_limits<float>::max();
constexpr float kDenormMin = std::numeric_limits<float>::denorm_min();
constexpr float kMinNormal = std::numeric_limits<float>::min();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr int kIntMax = std::numeric_limits<int>::max();

std::string str(const Vec3& p) {
    std::ostringstream s;
    s << std::setprecision(9) << "(" << p.x << ", " << p.y << ", " << p.z << ")";
    return s.str();
}

// Where two neighbour vectors first differ, with two entries either side: gtest prints only the
// first 32 entries of a vector, and large answers may differ far beyond them.
std::string firstDifference(const std::vector<Neighbor>& tree, const std::vector<Neighbor>& brute) {
    size_t i = 0;
    while (i < tree.size() && i < brute.size() && tree[i] == brute[i]) ++i;
    std::ostringstream s;
    s << "\nsizes " << tree.size() << " (kd-tree) and " << brute.size()
      << " (brute force), first difference at [" << i << "]:";
    auto show = [&](const char* name, const std::vector<Neighbor>& v) {
        s << "\n  " << name << ":";
        for (size_t j = i >= 2 ? i - 2 : 0; j < std::min(v.size(), i + 3); ++j) {
            s << " [" << j << "] ";
            PrintTo(v[j], &s);
        }
    };
    show("kd-tree    ", tree);
    show("brute force", brute);
    return s.str();
}

// What is wrong with a kd-tree answer on its own terms, or "" if nothing: it must be strictly
// increasing in the neighbour order (so sorted, with no id twice), with valid ids and the dist2
// that distance2() gives, all within the bound.
std::string selfCheck(const Points& points, const Vec3& p, float bound,
                      const std::vector<Neighbor>& v) {
    std::ostringstream s;
    for (size_t i = 0; i < v.size(); ++i) {
        if (v[i].id >= points.size()) {
            s << "id out of range at [" << i << "]";
        } else if (v[i].dist2 != distance2(points[v[i].id], p)) {
            s << "wrong dist2 at [" << i << "]";
        } else if (!(v[i].dist2 <= bound)) {
            s << "beyond the bound at [" << i << "]";
        } else if (i > 0 && !(v[i - 1] < v[i])) {
            s << "not strictly increasing at [" << i << "]";
        } else {
            continue;
        }
        return s.str();
    }
    return "";
}

// ---- Clouds. Braced initialisers evaluate the generator calls left to right.

Points uniformCloud(size_t n, float lo, float hi, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(lo, hi);
    Points p(n);
    for (Vec3& v : p) v = Vec3{u(rng), u(rng), u(rng)};
    return p;
}

// Coordinates of every magnitude from 1e-30 to 1e18, either sign: squared distances stay finite
// (at most 3 (2e18)^2 ~ 1.2e37) but span denormals to 1e37.
Points logScaleCloud(size_t n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> exponent(-30.0f, 18.0f);
    std::bernoulli_distribution negative(0.5);
    auto coordinate = [&] {
        float m = std::pow(10.0f, exponent(rng));
        return negative(rng) ? -m : m;
    };
    Points p(n);
    for (Vec3& v : p) v = Vec3{coordinate(), coordinate(), coordinate()};
    return p;
}

// Gaussian clusters of scales 1e-6 to 1e3 (log-uniform), of 1 to 100 points each, shuffled so
// that ids do not follow the clusters. Around centres up to 1e3 the smallest scales are below the
// float spacing, so those clusters collapse into duplicates and one-ulp lattices; `nested` puts
// every centre at the same point near the origin, where they stay resolved.
Points clusteredCloud(int clusters, bool nested, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> exponent(-6.0f, 3.0f), centre(-1000.0f, 1000.0f);
    std::uniform_int_distribution<int> count(1, 100);
    std::normal_distribution<float> gauss;
    Points p;
    for (int c = 0; c < clusters; ++c) {
        float scale = std::pow(10.0f, exponent(rng));
        Vec3 o = nested ? Vec3(0.25f, -0.5f, 1.0f) : Vec3{centre(rng), centre(rng), centre(rng)};
        for (int i = count(rng); i > 0; --i)
            p.push_back(o + scale * Vec3{gauss(rng), gauss(rng), gauss(rng)});
    }
    std::shuffle(p.begin(), p.end(), rng);
    return p;
}

// `distinct` random points, each repeated 2 to 50 times, shuffled (or not: copies adjacent).
Points duplicatedCloud(size_t distinct, bool shuffle, uint32_t seed) {
    std::mt19937 rng(seed);
    Points base = uniformCloud(distinct, -1.0f, 1.0f, seed + 1);
    std::uniform_int_distribution<int> copies(2, 50);
    Points p;
    for (const Vec3& v : base)
        for (int c = copies(rng); c > 0; --c) p.push_back(v);
    if (shuffle) std::shuffle(p.begin(), p.end(), rng);
    return p;
}

// An n x n x n integer lattice scaled by `spacing`, in shuffled order.
Points latticeCloud(int n, float spacing, uint32_t seed) {
    Points p;
    for (int x = 0; x < n; ++x)
        for (int y = 0; y < n; ++y)
            for (int z = 0; z < n; ++z) p.push_back(spacing * Vec3(float(x), float(y), float(z)));
    std::mt19937 rng(seed);
    std::shuffle(p.begin(), p.end(), rng);
    return p;
}

// Points on the plane z = 0.5 at half-integer x, y in [-5, 5] (so many duplicates and ties), or at
// random x, y when `grid` is false.
Points planeCloud(size_t n, bool grid, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> cell(-10, 10);
    std::uniform_real_distribution<float> u(-5.0f, 5.0f);
    Points p(n);
    for (Vec3& v : p)
        v = grid ? Vec3{0.5f * float(cell(rng)), 0.5f * float(cell(rng)), 0.5f}
                 : Vec3{u(rng), u(rng), 0.5f};
    return p;
}

// Points on a line: along x at integers in [-50, 50] (y = z = 1), or along (1, 2, 3) at integer
// multiples (every coordinate of a point is a multiple of the first).
Points lineCloud(size_t n, bool diagonal, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> t(-50, 50);
    Points p(n);
    for (Vec3& v : p) {
        float s = float(t(rng));
        v = diagonal ? s * Vec3(1.0f, 2.0f, 3.0f) : Vec3(s, 1.0f, 1.0f);
    }
    return p;
}

// ---- The cross-check.

struct Query {
    Vec3 p;
    const char* kind;
};

// Query points of six kinds, in turn: exactly a data point; a data point moved one ulp on one
// axis (just either side of a splitting plane); uniform inside the bounds; outside, 2 to 10 half
// extents from the centre; coordinates taken from three different data points (ties with split
// coordinates on every axis); and the midpoint of two data points (on a lattice: equidistant from
// many points).
std::vector<Query> makeQueries(const Points& points, int count, std::mt19937& rng) {
    Bounds3 b;
    for (const Vec3& v : points) b.extend(v);
    if (points.empty()) b = Bounds3{Vec3(-1.0f), Vec3(1.0f)};
    Vec3 centre = b.center();
    float extent = maxComponent(0.5f * (b.hi - b.lo));
    if (extent == 0.0f) extent = 1.0f;
    std::uniform_int_distribution<size_t> pick(0, points.empty() ? 0 : points.size() - 1);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), far(2.0f, 10.0f);
    std::uniform_int_distribution<int> axis(0, 2);
    std::normal_distribution<float> gauss;
    std::bernoulli_distribution up(0.5);
    std::vector<Query> queries;
    for (int q = 0; q < count; ++q) {
        int kind = points.empty() ? 2 : q % 6;
        switch (kind) {
            case 0:
                queries.push_back({points[pick(rng)], "on a data point"});
                break;
            case 1: {
                Vec3 p = points[pick(rng)];
                int a = axis(rng);
                p[a] = std::nextafter(p[a], up(rng) ? kInf : -kInf);
                queries.push_back({p, "one ulp off a data point"});
                break;
            }
            case 2: {
                Vec3 t{unit(rng), unit(rng), unit(rng)};
                queries.push_back({b.lo + t * (b.hi - b.lo), "inside the bounds"});
                break;
            }
            case 3: {
                Vec3 d = glm::normalize(Vec3{gauss(rng), gauss(rng), gauss(rng)});
                queries.push_back({centre + (far(rng) * extent) * d, "outside the bounds"});
                break;
            }
            case 4: {
                Vec3 p{points[pick(rng)].x, points[pick(rng)].y, points[pick(rng)].z};
                queries.push_back({p, "coordinates of three data points"});
                break;
            }
            default:
                queries.push_back({0.5f * (points[pick(rng)] + points[pick(rng)]),
                                   "midpoint of two data points"});
                break;
        }
    }
    return queries;
}

// One cloud, its kd-tree and brute force, and the tally of their comparisons. Only the first few
// failures are reported in full; the total is checked at the end.
class CrossCheck {
public:
    CrossCheck(std::string name, Points points)
        : name_(std::move(name)), points_(std::move(points)), tree_(points_), brute_(points_) {}
    ~CrossCheck() {
        EXPECT_EQ(failures_, 0u) << name_ << ": failing calls of " << calls_ << " (only the first "
                                 << kReported << " are reported)";
    }

    const Points& points() const { return points_; }
    const PhotonKdTree& tree() const { return tree_; }
    const BruteForceNeighbors& brute() const { return brute_; }

    /// `queries` query points (makeQueries), each tried with k in {0, 1, 2, 50, n, n + 1, INT_MAX}
    /// and with bounds 0, the smallest denormal and normal floats, the exact dist2 of the 1st, 2nd,
    /// 8th and 60th nearest points and the floats either side of two of them; the first
    /// `unbounded` queries also with FLT_MAX and infinity (there brute force sorts the whole
    /// cloud). `sampled` > 0 runs that many random (k, bound) pairs per query instead of all of
    /// them, for large clouds.
    void run(int queries, int unbounded, int sampled, uint32_t seed) {
        std::mt19937 rng(seed);
        const int n = int(points_.size());
        const int ks[] = {0, 1, 2, 50, n, n + 1, kIntMax};
        std::vector<float> d2(points_.size()), order;
        std::vector<Query> qs = makeQueries(points_, queries, rng);
        for (size_t qi = 0; qi < qs.size(); ++qi) {
            const Query& q = qs[qi];
            for (size_t i = 0; i < points_.size(); ++i) d2[i] = distance2(points_[i], q.p);
            std::vector<float> bounds = {0.0f, kDenormMin, kMinNormal};
            if (n > 0) {
                // The m-th smallest dist2, exactly: the bound then falls on a point (often on
                // several, tied), which must be included; the float just below excludes it.
                size_t m = std::min<size_t>(60, points_.size());
                order = d2;
                std::nth_element(order.begin(), order.begin() + ptrdiff_t(m - 1), order.end());
                std::sort(order.begin(), order.begin() + ptrdiff_t(m));
                auto nth = [&](size_t i) { return order[std::min(i, m) - 1]; };
                for (size_t i : {1, 2, 8, 60}) bounds.push_back(nth(i));
                bounds.push_back(std::nextafter(nth(60), 0.0f));
                bounds.push_back(std::nextafter(nth(8), kInf));
            }
            if (int(qi) < unbounded) {
                bounds.push_back(kMaxFloat);
                bounds.push_back(kInf);
            }
            // (k, bound index) pairs; k = -1 stands for withinRadius.
            std::vector<std::pair<int, size_t>> pairs;
            for (size_t bi = 0; bi < bounds.size(); ++bi) {
                pairs.push_back({-1, bi});
                for (int k : ks) pairs.push_back({k, bi});
            }
            if (sampled > 0 && int(qi) >= unbounded) {
                std::uniform_int_distribution<size_t> pick(0, pairs.size() - 1);
                for (int s = 0; s < sampled; ++s) {
                    auto [k, bi] = pairs[pick(rng)];
                    check(q, qi, k, bounds[bi], d2);
                }
            } else {
                for (auto [k, bi] : pairs) check(q, qi, k, bounds[bi], d2);
            }
        }
    }

    /// Compares one call (k < 0: withinRadius) of the kd-tree with brute force; `d2` holds every
    /// point's distance2 to the query.
    void check(const Query& q, size_t qi, int k, float bound, const std::vector<float>& d2) {
        ++calls_;
        if (k < 0) {
            tree_.withinRadius(q.p, bound, treeOut_);
            brute_.withinRadius(q.p, bound, bruteOut_);
        } else {
            tree_.nearest(q.p, k, bound, treeOut_);
            brute_.nearest(q.p, k, bound, bruteOut_);
        }
        size_t within =
            size_t(std::count_if(d2.begin(), d2.end(), [&](float d) { return d <= bound; }));
        size_t expected = k < 0 ? within : std::min(size_t(k), within);
        std::string problem = selfCheck(points_, q.p, bound, treeOut_);
        if (treeOut_ == bruteOut_ && treeOut_.size() == expected && problem.empty()) return;
        if (++failures_ > kReported) return;
        std::ostringstream what;
        what << std::setprecision(9) << name_ << " (" << points_.size() << " points), query #" << qi
             << " " << q.kind << " " << str(q.p) << ": ";
        if (k < 0) {
            what << "withinRadius(radius2 " << bound << ")";
        } else {
            what << "nearest(k " << k << ", maxDist2 " << bound << ")";
        }
        EXPECT_EQ(treeOut_, bruteOut_) << what.str() << firstDifference(treeOut_, bruteOut_);
        EXPECT_EQ(treeOut_.size(), expected)
            << what.str() << ": expected min(k, " << within << " points within the bound)";
        EXPECT_EQ(problem, "") << what.str();
    }

private:
    static constexpr size_t kReported = 5;
    std::string name_;
    Points points_;
    PhotonKdTree tree_;
    BruteForceNeighbors brute_;
    std::vector<Neighbor> treeOut_, bruteOut_;
    size_t calls_ = 0, failures_ = 0;
};

// Runs the cross-check on a cloud with settings that keep brute force cheap: all pairs and
// unbounded bounds on every query for small clouds, fewer as the cloud grows.
void crossCheck(const std::string& name, Points points, uint32_t seed, int queries = 60) {
    size_t n = points.size();
    int unbounded = n <= 2000 ? queries : 10;
    int sampled = n <= 20000 ? 0 : 12;
    CrossCheck(name, std::move(points)).run(queries, unbounded, sampled, seed);
}

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
    EXPECT_EQ(tree.depth(), 1);
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

TEST(PhotonKdTree, MemoryIsSixteenBytesPerPoint) {
    // A position and a packed index-and-axis per point, nothing else.
    for (size_t n : {0, 1, 7, 8, 9, 100, 10000, 40000}) {
        Points points = uniformCloud(n, -1.0f, 1.0f, uint32_t(n));
        PhotonKdTree tree(points);
        EXPECT_EQ(tree.size(), n);
        EXPECT_EQ(tree.memoryBytes(), 16 * n) << n << " points";
        EXPECT_EQ(BruteForceNeighbors(points).memoryBytes(), sizeof(Vec3) * n) << n << " points";
    }
}

// The depth of the median-split recursion, computed directly: a range of n splits into n / 2
// and n - n / 2 - 1.
int splitDepth(size_t n) {
    return n == 0 ? 0 : 1 + std::max(splitDepth(n / 2), splitDepth(n - n / 2 - 1));
}

TEST(PhotonKdTree, DepthIsCeilLog2OfCountPlusOne) {
    std::vector<size_t> sizes;
    for (size_t n = 0; n <= 300; ++n) sizes.push_back(n);
    for (size_t n : {511, 512, 513, 1023, 1024, 1025, 65535, 65536, 65537}) sizes.push_back(n);
    Points all = uniformCloud(65537, -1.0f, 1.0f, 91);
    for (size_t n : sizes) {
        PhotonKdTree tree(Points(all.begin(), all.begin() + ptrdiff_t(n)));
        int expected = int(std::ceil(std::log2(double(n) + 1.0)));
        EXPECT_EQ(tree.depth(), expected) << n << " points";
        EXPECT_EQ(tree.depth(), splitDepth(n)) << n << " points";
    }
}

}  // namespace
}  // namespace caustic
