#include "geometry/sphere.h"

#include "core/sampling.h"

namespace caustic {

std::optional<float> Sphere::intersect(const Ray& ray, float tMax) const {
    // Quadratic with the discriminant written as r^2 - |f + (b/a) d|^2, which keeps its precision
    // for rays far from a small sphere (Haines et al., Ray Tracing Gems, chapter 7).
    Vec3 f = ray.o - center;
    float a = glm::dot(ray.d, ray.d);
    float b = -glm::dot(f, ray.d);
    Vec3 l = f + (b / a) * ray.d;
    float disc = a * (radius * radius - glm::dot(l, l));
    if (disc < 0.0f) return std::nullopt;
    float c = glm::dot(f, f) - radius * radius;
    float q = b + std::copysign(std::sqrt(disc), b);
    float t0 = c / q, t1 = q / a;
    if (t0 > t1) std::swap(t0, t1);
    float t = t0 > 0.0f ? t0 : t1;
    if (!(t > 0.0f && t < tMax)) return std::nullopt;
    return t;
}

Vec2 Sphere::uv(const Vec3& point) const {
    Vec3 p = glm::normalize(point - center);
    float phi = std::atan2(p.y, p.x);
    if (phi < 0.0f) phi += 2.0f * kPi;
    float theta = std::acos(std::clamp(p.z, -1.0f, 1.0f));
    return Vec2(phi / (2.0f * kPi), theta / kPi);
}

void Sphere::hitPoint(const Ray& ray, float t, Vec3& p, Vec3& pError) const {
    // Reproject onto the surface: the error is then that of the projection (pbrt-v4, 6.8.5) plus
    // the rounding of adding the center back.
    Vec3 local = ray.o + t * ray.d - center;
    local *= radius / glm::length(local);
    p = center + local;
    pError = gamma(5) * glm::abs(local) + gamma(1) * glm::abs(p);
}

SurfaceSample Sphere::sample(Vec2 u) const {
    Vec3 n = sampleUniformSphere(u);
    Vec3 local = radius * n;
    SurfaceSample s;
    s.p = center + local;
    s.pError = gamma(5) * glm::abs(local) + gamma(1) * glm::abs(s.p);
    s.n = n;
    s.pdfArea = 1.0f / area();
    return s;
}

}  // namespace caustic
