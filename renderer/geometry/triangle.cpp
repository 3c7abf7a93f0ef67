#include "geometry/triangle.h"

#include <algorithm>
#include <limits>

namespace caustic {
namespace {

// The barycentric t cannot tell the hit from the ray's origin: decide in double with the
// triangle's plane. The inputs are floats, so the plane distance is exact to a few ulps of double;
// accepting only t above that bound keeps a ray that starts on the triangle (after its origin
// offset) from hitting it, while a real hit 1e-5 in front, at a crease or a room's corner, is no
// longer lost (pbrt-v4's bound grows with the triangle's size and rejects those: light leaks at
// corners). A ray that grazes the plane meets it anywhere, perhaps far outside the triangle and
// its box, where an accelerator culling by boxes never looks: the plane's t must also agree with
// the barycentric t (`tBary`) within that one's error (`errT`), which places the hit on the
// triangle.
std::optional<TriangleHit> decideNearOrigin(const Ray& ray, float tMax, const Vec3& p0,
                                            const Vec3& p1, const Vec3& p2, double tBary,
                                            double errT, TriangleHit hit) {
    glm::dvec3 a(p0), o(ray.o), d(ray.d);
    glm::dvec3 n = glm::cross(glm::dvec3(p1) - a, glm::dvec3(p2) - a);
    double denom = glm::dot(n, d);
    if (denom == 0.0) return std::nullopt;
    double t = glm::dot(n, a - o) / denom;
    double bound = 16.0 * std::numeric_limits<double>::epsilon() *
                   glm::dot(glm::abs(n), glm::abs(a) + glm::abs(o)) / std::abs(denom);
    if (!(t > bound && std::abs(t - tBary) <= errT + bound)) return std::nullopt;
    hit.t = static_cast<float>(t);
    if (!(hit.t > 0.0f && hit.t < tMax)) return std::nullopt;
    return hit;
}

// The edge test in double for edge functions the float test cannot sign: a ray through an edge or
// a vertex (pbrt-v4 recomputes those in double too), a tiny triangle, or a ray in the triangle's
// plane. Each product of two floats is exact in double, so each edge function is rounded once and
// its sign is right: a ray exactly on a shared edge hits one of the two triangles, and none
// outside. The barycentrics are then exact to double precision for the translated triangle, and
// so is t, their blend of the vertices' depths (1 / d_z scales a depth to t): the hit lies
// on the triangle even for a ray in its plane, whose t from the plane is anywhere. Translating the
// vertices to the origin in float moved them by half an ulp of their coordinates, and the plane
// decides a t within that of zero.
std::optional<TriangleHit> intersectInDouble(const WatertightRay& wr, float tMax, const Vec3& p0t,
                                             const Vec3& p1t, const Vec3& p2t, const Vec3& p0,
                                             const Vec3& p1, const Vec3& p2) {
    auto edge = [](const Vec3& a, const Vec3& b) {
        return double(a.x) * double(b.y) - double(a.y) * double(b.x);
    };
    double e0 = edge(p1t, p2t), e1 = edge(p2t, p0t), e2 = edge(p0t, p1t);
    if ((e0 < 0 || e1 < 0 || e2 < 0) && (e0 > 0 || e1 > 0 || e2 > 0)) return std::nullopt;
    double det = e0 + e1 + e2;
    if (det == 0.0) return std::nullopt;
    TriangleHit hit{float(e0 / det), float(e1 / det), float(e2 / det), 0.0f};
    const double sz = wr.sz;
    double tBary = (e0 * p0t.z + e1 * p1t.z + e2 * p2t.z) * sz / det;
    double maxDepth = std::max({std::abs(p0[wr.kz]), std::abs(p1[wr.kz]), std::abs(p2[wr.kz])});
    double errT =
        4.0 * std::numeric_limits<float>::epsilon() * std::abs(sz) * (maxDepth + std::abs(wr.oz));
    if (tBary < -errT) return std::nullopt;
    if (tBary <= errT) return decideNearOrigin(wr.ray, tMax, p0, p1, p2, tBary, errT, hit);
    hit.t = float(tBary);
    if (!(hit.t > 0.0f && hit.t < tMax)) return std::nullopt;
    return hit;
}

}  // namespace

std::optional<TriangleHit> intersectTriangle(const WatertightRay& wr, float tMax, const Vec3& p0,
                                             const Vec3& p1, const Vec3& p2) {
    // Translate the vertices to the ray origin, permute so that the ray's largest direction
    // component is z, and shear so that the ray runs along +z. z is sheared below, by the scale.
    // (Components are loaded from memory by index: permuting a vector held in registers would
    // spill it to the stack on every test, and glm's operator[] would branch on the index.)
    const int kx = wr.kx, ky = wr.ky, kz = wr.kz;
    Vec3 p0t, p1t, p2t;
    auto shear = [&](const Vec3& p, Vec3& pt) {
        shearVertex(wr, component(p, kx), component(p, ky), component(p, kz), pt.x, pt.y);
        pt.z = component(p, kz) - wr.oz;
    };
    shear(p0, p0t);
    shear(p1, p1t);
    shear(p2, p2t);

    // Edge functions. Where one is zero or below the normal floats, its float value may have
    // underflowed and its sign be wrong (a ray in the plane of a triangle 1e-45 thick "hit" it
    // outside its edges): decide in double, where the products of floats are exact.
    float e0 = differenceOfProducts(p1t.x, p2t.y, p1t.y, p2t.x);
    float e1 = differenceOfProducts(p2t.x, p0t.y, p2t.y, p0t.x);
    float e2 = differenceOfProducts(p0t.x, p1t.y, p0t.y, p1t.x);
    if (edgeFunctionsTiny(e0, e1, e2))
        return intersectInDouble(wr, tMax, p0t, p1t, p2t, p0, p1, p2);
    if (edgeSignsDisagree(e0, e1, e2)) return std::nullopt;
    float det = e0 + e1 + e2;
    // Scaled distance, compared against the range without dividing.
    const float sz = wr.sz;
    p0t.z *= sz;
    p1t.z *= sz;
    p2t.z *= sz;
    float tScaled = e0 * p0t.z + e1 * p1t.z + e2 * p2t.z;
    float invDet = 1.0f / det;
    TriangleHit hit{e0 * invDet, e1 * invDet, e2 * invDet, tScaled * invDet};

    // Is t conservatively positive? t is a convex combination of the vertices' depths z_i (the
    // barycentrics are non-negative here), so when every z_i exceeds its rounding error it is, and
    // the float t is good enough to compare with tMax.
    float maxZt = maxComponent(glm::abs(Vec3(p0t.z, p1t.z, p2t.z)));
    float deltaZ = gamma(3) * maxZt;
    float minZt = std::min(p0t.z, std::min(p1t.z, p2t.z));
    if (minZt > deltaZ) return hit.t < tMax ? std::optional(hit) : std::nullopt;
    // Otherwise pbrt-v4's bound on t's error (section 6.8.7). It multiplies the edge functions'
    // error by the depth, so it is loose for large triangles and distant grazing rays.
    float maxXt = maxComponent(glm::abs(Vec3(p0t.x, p1t.x, p2t.x)));
    float maxYt = maxComponent(glm::abs(Vec3(p0t.y, p1t.y, p2t.y)));
    float deltaX = gamma(5) * (maxXt + maxZt);
    float deltaY = gamma(5) * (maxYt + maxZt);
    float deltaE = 2.0f * (gamma(2) * maxXt * maxYt + deltaY * maxXt + deltaX * maxYt);
    float maxE = maxComponent(glm::abs(Vec3(e0, e1, e2)));
    float deltaT =
        3.0f * (gamma(3) * maxE * maxZt + deltaE * maxZt + deltaZ * maxE) * std::abs(invDet);
    if (hit.t > deltaT) return hit.t < tMax ? std::optional(hit) : std::nullopt;
    if (hit.t < -deltaT) return std::nullopt;
    // Too close to the origin for the float bound: decide t, and compare it with tMax, in double,
    // so that intersect() and occluded() agree on the same t.
    return decideNearOrigin(wr.ray, tMax, p0, p1, p2, hit.t, deltaT, hit);
}

}  // namespace caustic
