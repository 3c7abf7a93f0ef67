// A kd-tree leaf's primitives, stored with it, and the watertight test's first step for eight of
// them at once. A leaf of n primitives is 10 n words in one array: the n triangles' vertex
// coordinates, one coordinate at a time (vertex 0's x of all n, its y, its z, then vertex 1's,
// vertex 2's), then the n primitive indices. So each coordinate of eight triangles is one vector
// load, as in Embree's Triangle4v, but a leaf is not padded to a multiple of the vector: its lanes
// past n read the next coordinate's words and are masked off. Triangles only: a lane that is
// another primitive (sphere, quad) has zero vertices, and its primitive word is marked.
#pragma once

#include <cstdint>
#include <cstring>

#include "geometry/triangle.h"

#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace caustic {

namespace kd_leaf {

constexpr int kLanes = 8;
constexpr uint32_t kWordsPerPrim = 10;
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

}  // namespace leaf_simd

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
    const Ints keep = tiny | ~(negative & positive);
#if defined(__AVX__)
    uint32_t mask = uint32_t(_mm256_movemask_ps((__m256)keep));
#else
    uint32_t mask = 0;
    for (int l = 0; l < kd_leaf::kLanes; ++l) mask |= uint32_t(keep[l] & 1) << l;
#endif
    const uint32_t left = n - first;
    return left < kd_leaf::kLanes ? mask & ((1u << left) - 1u) : mask;
}

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

}  // namespace caustic
