// Point clouds and the brute-force cross-check shared by the photon kd-tree tests
// (photon_kdtree_test.cpp: hand-checked answers and properties of the tree;
// photon_kdtree_cross_check_test.cpp: every cloud against brute force).
#pragma once

#include <gtest/gtest.h>

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

namespace kdtree_test {

using Points = std::vector<Vec3>;

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kMaxFloat = std::numeric_limits<float>::max();
constexpr float kDenormMin = std::numeric_limits<float>::denorm_min();
constexpr float kMinNormal = std::numeric_limits<float>::min();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr int kIntMax = std::numeric_limits<int>::max();

inline std::string str(const Vec3& p) {
    std::ostringstream s;
    s << std::setprecision(9) << "(" << p.x << ", " << p.y << ", " << p.z << ")";
    return s.str();
}

// Where two neighbour vectors first differ, with two entries either side: gtest prints only the
// first 32 entries of a vector, and large answers may differ far beyond them.
inline std::string firstDifference(const std::vector<Neighbor>& tree,
                                   const std::vector<Neighbor>& brute) {
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
inline std::string selfCheck(const Points& points, const Vec3& p, float bound,
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

inline Points uniformCloud(size_t n, float lo, float hi, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(lo, hi);
    Points p(n);
    for (Vec3& v : p) v = Vec3{u(rng), u(rng), u(rng)};
    return p;
}

// Coordinates of every magnitude from 1e-30 to 1e18, either sign: squared distances stay finite
// (at most 3 (2e18)^2 ~ 1.2e37) but span denormals to 1e37.
inline Points logScaleCloud(size_t n, uint32_t seed) {
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
inline Points clusteredCloud(int clusters, bool nested, uint32_t seed) {
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
inline Points duplicatedCloud(size_t distinct, bool shuffle, uint32_t seed) {
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
inline Points latticeCloud(int n, float spacing, uint32_t seed) {
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
inline Points planeCloud(size_t n, bool grid, uint32_t seed) {
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
inline Points lineCloud(size_t n, bool diagonal, uint32_t seed) {
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
inline std::vector<Query> makeQueries(const Points& points, int count, std::mt19937& rng) {
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
inline void crossCheck(const std::string& name, Points points, uint32_t seed, int queries = 60) {
    size_t n = points.size();
    int unbounded = n <= 2000 ? queries : 10;
    int sampled = n <= 20000 ? 0 : 12;
    CrossCheck(name, std::move(points)).run(queries, unbounded, sampled, seed);
}

}  // namespace kdtree_test
}  // namespace caustic
