#include "geometry/triangle.h"

#include <limits>

namespace caustic {
namespace {

// a*b - c*d with one rounding error, by Kahan's algorithm with FMA.
float differenceOfProducts(float a, float b, float c, float d) {
    float cd = c * d;
    float err = std::fma(-c, d, cd);
    float dop = std::fma(a, b, -cd);
    return dop + err;
}

int maxDimension(const Vec3& v) {
    return v.x > v.y ? (v.x > v.z ? 0 : 2) : (v.y > v.z ? 1 : 2);
}

Vec3 permute(const Vec3& v, int x, int y, int z) {
    return Vec3(v[x], v[y], v[z]);
}

// The float bound cannot tell t from zero: decide in double with the triangle's plane. The inputs
// are floats, so the plane distance is exact to a few ulps of double; accepting only t above that
// bound keeps a ray that starts on the triangle (after its origin offset) from hitting it, while a
// real hit 1e-5 in front, at a crease or a room's corner, is no longer lost (pbrt-v4's bound grows
// with the triangle's size and rejects those: light leaks at corners).
std::optional<TriangleHit> decideNearOrigin(const Ray& ray, float tMax, const Vec3& p0,
                                            const Vec3& p1, const Vec3& p2, TriangleHit hit) {
    glm::dvec3 a(p0), o(ray.o), d(ray.d);
    glm::dvec3 n = glm::cross(glm::dvec3(p1) - a, glm::dvec3(p2) - a);
    double denom = glm::dot(n, d);
    if (denom == 0.0) return std::nullopt;
    double t = glm::dot(n, a - o) / denom;
    double bound = 16.0 * std::numeric_limits<double>::epsilon() *
                   glm::dot(glm::abs(n), glm::abs(a) + glm::abs(o)) / std::abs(denom);
    if (!(t > bound)) return std::nullopt;
    hit.t = static_cast<float>(t);
    if (!(hit.t > 0.0f && hit.t < tMax)) return std::nullopt;
    return hit;
}

}  // namespace

WatertightRay::WatertightRay(const Ray& r) : ray(r) {
    kz = maxDimension(glm::abs(r.d));
    kx = kz + 1 == 3 ? 0 : kz + 1;
    ky = kx + 1 == 3 ? 0 : kx + 1;
    Vec3 d = permute(r.d, kx, ky, kz);
    sx = -d.x / d.z;
    sy = -d.y / d.z;
    sz = 1.0f / d.z;
}

std::optional<TriangleHit> intersectTriangle(const WatertightRay& wr, float tMax, const Vec3& p0,
                                             const Vec3& p1, const Vec3& p2) {
    // Translate the vertices to the ray origin and permute so that the ray's largest direction
    // component is z.
    const Ray& ray = wr.ray;
    const int kx = wr.kx, ky = wr.ky, kz = wr.kz;
    Vec3 p0t = permute(p0 - ray.o, kx, ky, kz);
    Vec3 p1t = permute(p1 - ray.o, kx, ky, kz);
    Vec3 p2t = permute(p2 - ray.o, kx, ky, kz);

    // Shear so that the ray runs along +z.
    const float sx = wr.sx, sy = wr.sy, sz = wr.sz;
    p0t.x += sx * p0t.z;
    p0t.y += sy * p0t.z;
    p1t.x += sx * p1t.z;
    p1t.y += sy * p1t.z;
    p2t.x += sx * p2t.z;
    p2t.y += sy * p2t.z;

    // Edge functions, recomputed in double where a float one is exactly zero.
    float e0 = differenceOfProducts(p1t.x, p2t.y, p1t.y, p2t.x);
    float e1 = differenceOfProducts(p2t.x, p0t.y, p2t.y, p0t.x);
    float e2 = differenceOfProducts(p0t.x, p1t.y, p0t.y, p1t.x);
    if (e0 == 0.0f || e1 == 0.0f || e2 == 0.0f) {
        e0 = static_cast<float>(double(p1t.x) * double(p2t.y) - double(p1t.y) * double(p2t.x));
        e1 = static_cast<float>(double(p2t.x) * double(p0t.y) - double(p2t.y) * double(p0t.x));
        e2 = static_cast<float>(double(p0t.x) * double(p1t.y) - double(p0t.y) * double(p1t.x));
    }
    if ((e0 < 0 || e1 < 0 || e2 < 0) && (e0 > 0 || e1 > 0 || e2 > 0)) return std::nullopt;
    float det = e0 + e1 + e2;
    if (det == 0.0f) return std::nullopt;

    // Scaled distance, compared against the range without dividing.
    p0t.z *= sz;
    p1t.z *= sz;
    p2t.z *= sz;
    float tScaled = e0 * p0t.z + e1 * p1t.z + e2 * p2t.z;
    if (det < 0 && (tScaled >= 0 || tScaled < tMax * det)) return std::nullopt;
    if (det > 0 && (tScaled <= 0 || tScaled > tMax * det)) return std::nullopt;

    float invDet = 1.0f / det;
    TriangleHit hit{e0 * invDet, e1 * invDet, e2 * invDet, tScaled * invDet};

    // Reject hits whose t is not conservatively positive. t is a convex combination of the
    // vertices' depths z_i (the barycentrics are non-negative here), so when every z_i exceeds its
    // rounding error, t > 0 holds. Only otherwise use pbrt-v4's bound (section 6.8.7), which
    // multiplies the edge functions' error by the depth and, for distant grazing rays, rejects hits
    // far in front of the origin.
    float maxZt = maxComponent(glm::abs(Vec3(p0t.z, p1t.z, p2t.z)));
    float deltaZ = gamma(3) * maxZt;
    float minZt = std::min(p0t.z, std::min(p1t.z, p2t.z));
    if (minZt > deltaZ) return hit;
    float maxXt = maxComponent(glm::abs(Vec3(p0t.x, p1t.x, p2t.x)));
    float maxYt = maxComponent(glm::abs(Vec3(p0t.y, p1t.y, p2t.y)));
    float deltaX = gamma(5) * (maxXt + maxZt);
    float deltaY = gamma(5) * (maxYt + maxZt);
    float deltaE = 2.0f * (gamma(2) * maxXt * maxYt + deltaY * maxXt + deltaX * maxYt);
    float maxE = maxComponent(glm::abs(Vec3(e0, e1, e2)));
    float deltaT =
        3.0f * (gamma(3) * maxE * maxZt + deltaE * maxZt + deltaZ * maxE) * std::abs(invDet);
    if (hit.t > deltaT) return hit;
    return decideNearOrigin(ray, tMax, p0, p1, p2, hit);
}

}  // namespace caustic
