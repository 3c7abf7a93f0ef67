// Watertight ray-triangle intersection (Woop, Benthin and Wald 2013, "Watertight Ray/Triangle
// Intersection", JCGT 2(1)), as in pbrt-v4 section 6.5.3, with its conservative bound on t.
#pragma once

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
