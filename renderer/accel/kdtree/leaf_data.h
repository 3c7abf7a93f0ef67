// A kd-tree leaf's primitives, stored with it, and the tests that cull them eight at once: the
// bounding boxes of its blocks of eight, and the watertight test's first step. A leaf of n
// primitives in b = ceil(n / 8) blocks is 10 n + 6 b words in one array: the n triangles' vertex
// coordinates, one coordinate at a time (vertex 0's x of all n, its y, its z, then vertex 1's,
// vertex 2's), then the n primitive indices, then the blocks' boxes (the low x of all b, low y,
// low z, high x, high y, high z). So each coordinate of eight triangles is one vector load, as in
// Embree's Triangle4v, and so is each bound of eight blocks; a leaf is not padded to a multiple of
// the vector: its lanes past n (or b) read the next words and are masked off. The builder orders
// a leaf's primitives so that each block is a spatial cluster with a small box (a median split,
// as a BVH's leaves): a ray through the leaf's cell tests only the blocks whose boxes it meets.
// Triangles only: a lane that is another primitive (sphere, quad) has zero vertices, and its
// primitive word is marked.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>

#include "core/bounds.h"
#include "geometry/triangle.h"

#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace caustic {

namespace kd_leaf {

constexpr int kLanes = 8;
/// Words after the last leaf, so that its vector loads stay inside the array.
constexpr uint32_t kPadWords = kLanes;

/// Word offsets, within a leaf of n primitives, of coordinate `axis` of vertex `v` and of the
/// primitive indices.
inline uint32_t coordinate(uint32_t n, int v, int axis) {
    return uint32_t(3 * v + axis) * n;
}
inline uint32_t primitives(uint32_t n) {
    return 9 * n;
}
/// The blocks of kLanes primitives in a leaf of n, and the word offset of bound `side` (0 low, 1
/// high) on `axis` of the first block's box.
inline uint32_t blocks(uint32_t n) {
    return (n + kLanes - 1) / kLanes;
}
inline uint32_t blockBound(uint32_t n, int side, int axis) {
    return primitives(n) + n + uint32_t(3 * side + axis) * blocks(n);
}
/// The words of a leaf of n primitives.
inline uint32_t words(uint32_t n) {
    return primitives(n) + n + 6 * blocks(n);
}

/// The top bit of a primitive word marks a primitive other than a triangle, so that the traversal
/// tells the kinds apart without reading the primitive's record: a load that missed the cache on
/// incoherent rays. The builder checks that primitive indices stay below it.
constexpr uint32_t kOtherKind = 1u << 31;

}  // namespace kd_leaf

// GCC notes, for every function below, that without AVX it passes 32-byte vectors differently
// than with it: they are inline and never cross a library's interface.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace leaf_simd {

// kLanes floats or ints in one vector (GCC's and Clang's vector extensions: one AVX register
// where the target has AVX, two SSE registers where it has not).
using Floats = float __attribute__((vector_size(sizeof(float) * kd_leaf::kLanes)));
using Ints = int32_t __attribute__((vector_size(sizeof(int32_t) * kd_leaf::kLanes)));

inline Floats load(const uint32_t* p) {
    Floats v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

inline Floats splat(float f) {
    return Floats{} + f;
}

// a * b + c with one rounding, lane by lane as std::fma does it.
inline Floats fma(Floats a, Floats b, Floats c) {
#if defined(__AVX__) && defined(__FMA__)
    static_assert(kd_leaf::kLanes == 8);
    return _mm256_fmadd_ps(a, b, c);
#else
    for (int l = 0; l < kd_leaf::kLanes; ++l) a[l] = std::fma(a[l], b[l], c[l]);
    return a;
#endif
}

inline Floats abs(Floats v) {
    Ints bits;
    std::memcpy(&bits, &v, sizeof v);
    bits &= 0x7fffffff;
    std::memcpy(&v, &bits, sizeof v);
    return v;
}

// differenceOfProducts (geometry/triangle.h), lane by lane, with the same operations.
inline Floats differenceOfProducts(Floats a, Floats b, Floats c, Floats d) {
    Floats cd = c * d;
    Floats err = fma(-c, d, cd);
    Floats dop = fma(a, b, -cd);
    return dop + err;
}

// Lanes of `a` where `mask` is set, else of `b`.
inline Floats select(Ints mask, Floats a, Floats b) {
    Ints ia, ib;
    std::memcpy(&ia, &a, sizeof a);
    std::memcpy(&ib, &b, sizeof b);
    ia = (ia & mask) | (ib & ~mask);
    std::memcpy(&a, &ia, sizeof a);
    return a;
}

inline uint32_t movemask(Ints v) {
#if defined(__AVX__)
    static_assert(kd_leaf::kLanes == 8);
    return uint32_t(_mm256_movemask_ps((__m256)v));
#else
    uint32_t mask = 0;
    for (int l = 0; l < kd_leaf::kLanes; ++l) mask |= uint32_t(v[l] & 1) << l;
    return mask;
#endif
}

}  // namespace leaf_simd

/// A ray set up for the test of eight block boxes at once: its origin and inverse direction in
/// every lane, and the direction's signs (directionSignBits).
struct BlockRay {
    leaf_simd::Floats org[3], invDir[3];
    uint32_t negative;

    BlockRay(const Vec3& o, const Vec3& inv, uint32_t negativeBits) : negative(negativeBits) {
        for (int a = 0; a < 3; ++a) {
            org[a] = leaf_simd::splat(component(o, a));
            invDir[a] = leaf_simd::splat(component(inv, a));
        }
    }
};

/// Box i of boxes stored as six rows of `stride` words from `rows` (low x of every box, low y,
/// low z, high x, high y, high z; float bits): the layout of a leaf's block boxes (from
/// kd_leaf::blockBound(n, 0, 0), stride kd_leaf::blocks(n)) and of the top cells' boxes, which
/// meetsBoxes reads eight at a time.
inline void storeBoxInRows(uint32_t* rows, uint32_t stride, uint32_t i, const Bounds3& box) {
    for (int a = 0; a < 3; ++a) {
        rows[uint32_t(a) * stride + i] = std::bit_cast<uint32_t>(component(box.lo, a));
        rows[uint32_t(3 + a) * stride + i] = std::bit_cast<uint32_t>(component(box.hi, a));
    }
}
inline Bounds3 loadBoxInRows(const uint32_t* rows, uint32_t stride, uint32_t i) {
    Bounds3 box;
    for (int a = 0; a < 3; ++a) {
        setComponent(box.lo, a, std::bit_cast<float>(rows[uint32_t(a) * stride + i]));
        setComponent(box.hi, a, std::bit_cast<float>(rows[uint32_t(3 + a) * stride + i]));
    }
    return box;
}

/// What meetsBoxes finds of eight boxes: the boxes the ray meets, one bit each, and each lane's
/// range of the ray inside its box.
struct BoxHits {
    uint32_t mask;
    leaf_simd::Floats tNear, tFar;
};

/// Boxes first .. first + 7 of the `count` boxes stored as six rows of `stride` words from `rows`
/// (low x of every box, low y, low z, high x, high y, high z) that the ray meets within [t0, t1].
/// clipToBox's slab test (core/bounds.h), the same operations lane by lane, so that a box is
/// culled only where clipToBox would say the ray misses it, and a lane's range is the one
/// clipToBox would clip [t0, t1] to. Lanes past the last box are not set.
inline BoxHits meetsBoxes(const uint32_t* rows, uint32_t stride, uint32_t count, uint32_t first,
                          const BlockRay& r, float t0, float t1) {
    using namespace leaf_simd;
    Floats tMin = splat(t0), tMax = splat(t1);
    const Floats slack = splat(1.0f + kRayBoxSlack);
    for (int a = 0; a < 3; ++a) {
        const int flip = int((r.negative >> a) & 1u);
        const Floats tNear =
            (load(rows + uint32_t(3 * flip + a) * stride + first) - r.org[a]) * r.invDir[a];
        const Floats tFar =
            (load(rows + uint32_t(3 * (flip ^ 1) + a) * stride + first) - r.org[a]) * r.invDir[a] *
            slack;
        tMin = select(tNear > tMin, tNear, tMin);
        tMax = select(tFar < tMax, tFar, tMax);
    }
    const uint32_t mask = movemask(tMin <= tMax);
    const uint32_t left = count - first;
    return {left < kd_leaf::kLanes ? mask & ((1u << left) - 1u) : mask, tMin, tMax};
}

/// Blocks first .. first + 7 of the leaf of n primitives at `leaf` whose boxes the ray meets
/// within [0, tMax]: one bit each (meetsBoxes).
inline uint32_t meetsBlocks(const uint32_t* leaf, uint32_t n, uint32_t first, const BlockRay& r,
                            float tMax) {
    return meetsBoxes(leaf + kd_leaf::blockBound(n, 0, 0), kd_leaf::blocks(n), kd_leaf::blocks(n),
                      first, r, 0.0f, tMax)
        .mask;
}

/// Lanes first .. first + 7 of the leaf of n primitives at `leaf`: those whose triangles
/// intersectTriangle may hit, one bit each. Its float edge test, for every lane at once, with the
/// same operations as shearVertex, differenceOfProducts and edgeTestMayHit (geometry/triangle.h),
/// so that a lane's bit is set exactly where intersectTriangle does not reject the lane's triangle
/// by the signs of its edge functions. Lanes of zero vertices (primitives other than triangles)
/// are always set; lanes past the leaf's end are not.
inline uint32_t mayHitLanes(const uint32_t* leaf, uint32_t n, uint32_t first,
                            const WatertightRay& wr) {
    using namespace leaf_simd;
    const Floats ox = splat(wr.ox), oy = splat(wr.oy), oz = splat(wr.oz);
    const Floats sx = splat(wr.sx), sy = splat(wr.sy);
    const uint32_t* c = leaf + first;
    Floats x[3], y[3];
    for (int v = 0; v < 3; ++v) {
        const Floats z = load(c + kd_leaf::coordinate(n, v, wr.kz)) - oz;
        x[v] = fma(sx, z, load(c + kd_leaf::coordinate(n, v, wr.kx)) - ox);
        y[v] = fma(sy, z, load(c + kd_leaf::coordinate(n, v, wr.ky)) - oy);
    }
    const Floats e0 = differenceOfProducts(x[1], y[2], y[1], x[2]);
    const Floats e1 = differenceOfProducts(x[2], y[0], y[2], x[0]);
    const Floats e2 = differenceOfProducts(x[0], y[1], y[0], x[1]);
    const Floats smallest = splat(std::numeric_limits<float>::min()), zero{};
    const Ints tiny = (abs(e0) < smallest) | (abs(e1) < smallest) | (abs(e2) < smallest);
    const Ints negative = (e0 < zero) | (e1 < zero) | (e2 < zero);
    const Ints positive = (e0 > zero) | (e1 > zero) | (e2 > zero);
    const uint32_t mask = movemask(tiny | ~(negative & positive));
    const uint32_t left = n - first;
    return left < kd_leaf::kLanes ? mask & ((1u << left) - 1u) : mask;
}

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

}  // namespace caustic
