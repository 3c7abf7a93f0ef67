// Watertight ray-triangle intersection (Woop, Benthin and Wald 2013, "Watertight Ray/Triangle
// Intersection", JCGT 2(1)), as in pbrt-v4 section 6.5.3, with its conservative bound on t.
#pragma once

#include <cmath>
#include <limits>
#include <optional>

#include "core/ray.h"

namespace caustic {

struct TriangleHit {
    float b0, b1, b2;  ///< Barycentrics of vertices 0, 1, 2.
    float t;
};

/// A ray with the per-ray part of the watertight test done once (Woop et al. 2013, section 3): the
/// axis permutation that makes its largest direction component z, and the shear to +z.
struct WatertightRay {
    Ray ray;
    int kx, ky, kz;
    float sx, sy, sz;
    float ox, oy, oz;  ///< The origin, permuted.
    explicit WatertightRay(const Ray& r);
};

// Inline: every accelerator query builds one, and a call per ray cost the kd-tree's incoherent
// rays a few percent.
inline WatertightRay::WatertightRay(const Ray& r) : ray(r) {
    const Vec3 a = glm::abs(r.d);
    kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    kx = kz + 1 == 3 ? 0 : kz + 1;
    ky = kx + 1 == 3 ? 0 : kx + 1;
    const float dz = component(r.d, kz);
    sx = -component(r.d, kx) / dz;
    sy = -component(r.d, ky) / dz;
    sz = 1.0f / dz;
    ox = component(r.o, kx);
    oy = component(r.o, ky);
    oz = component(r.o, kz);
}

/// a*b - c*d with one rounding error, by Kahan's algorithm with FMA (pbrt-v4, section B.2.9).
inline float differenceOfProducts(float a, float b, float c, float d) {
    float cd = c * d;
    float err = std::fma(-c, d, cd);
    float dop = std::fma(a, b, -cd);
    return dop + err;
}

/// A vertex coordinate pair translated to the ray's origin, permuted (x, y, z = components kx, ky,
/// kz) and sheared so that the ray runs along +z: x and y of the vertex in the sheared frame. Its
/// z, `vz - wr.oz`, is sheared by the scale `sz` later. The multiply-adds are explicit, so that
/// every caller (intersectTriangle, a kd-tree leaf's test of eight triangles at once) computes the
/// same bits whatever the compiler's floating-point contraction.
inline void shearVertex(const WatertightRay& wr, float vx, float vy, float vz, float& x, float& y) {
    const float z = vz - wr.oz;
    x = std::fma(wr.sx, z, vx - wr.ox);
    y = std::fma(wr.sy, z, vy - wr.oy);
}

/// Whether an edge function is zero or below the normal floats, so that its float sign may be
/// wrong: intersectTriangle then decides in double.
inline bool edgeFunctionsTiny(float e0, float e1, float e2) {
    constexpr float kSmallest = std::numeric_limits<float>::min();
    return std::abs(e0) < kSmallest || std::abs(e1) < kSmallest || std::abs(e2) < kSmallest;
}
/// Whether the edge functions have opposite signs: the ray misses the triangle.
inline bool edgeSignsDisagree(float e0, float e1, float e2) {
    return (e0 < 0 || e1 < 0 || e2 < 0) && (e0 > 0 || e1 > 0 || e2 > 0);
}
/// The float edge functions' verdict: false where intersectTriangle certainly misses, true where
/// it may hit or decides in double.
inline bool edgeTestMayHit(float e0, float e1, float e2) {
    return edgeFunctionsTiny(e0, e1, e2) || !edgeSignsDisagree(e0, e1, e2);
}

/// Nearest hit of the ray with triangle (p0, p1, p2) in (0, tMax). Rays through shared edges and
/// vertices hit exactly one of the triangles that share them; zero-area triangles are never hit.
std::optional<TriangleHit> intersectTriangle(const WatertightRay& ray, float tMax, const Vec3& p0,
                                             const Vec3& p1, const Vec3& p2);
inline std::optional<TriangleHit> intersectTriangle(const Ray& ray, float tMax, const Vec3& p0,
                                                    const Vec3& p1, const Vec3& p2) {
    return intersectTriangle(WatertightRay(ray), tMax, p0, p1, p2);
}

/// Interpolated point and its error bound (pbrt-v4, section 6.8.5: gamma(7) sum |b_i p_i|).
inline void triangleHitPoint(const TriangleHit& h, const Vec3& p0, const Vec3& p1, const Vec3& p2,
                             Vec3& p, Vec3& pError) {
    p = h.b0 * p0 + h.b1 * p1 + h.b2 * p2;
    pError = gamma(7) * (glm::abs(h.b0 * p0) + glm::abs(h.b1 * p1) + glm::abs(h.b2 * p2));
}

/// Unit normal of the counter-clockwise front face.
inline Vec3 triangleNormal(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
    return glm::normalize(glm::cross(p1 - p0, p2 - p0));
}

}  // namespace caustic
