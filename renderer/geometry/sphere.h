// Spheres: intersection with a precision-aware quadratic, reprojected hit points, area sampling.
#pragma once

#include <optional>

#include "core/bounds.h"
#include "core/ray.h"
#include "geometry/hit.h"

namespace caustic {

struct Sphere {
    Vec3 center;
    float radius;

    Bounds3 bounds() const {
        Bounds3 b;
        b.extend(center - Vec3(radius));
        b.extend(center + Vec3(radius));
        return b;
    }
    float area() const { return 4.0f * kPi * radius * radius; }

    /// Nearest hit distance in (0, tMax). The outward normal is the front side.
    std::optional<float> intersect(const Ray& ray, float tMax) const;
    /// Surface parameters (phi / 2pi, theta / pi) of a point on the sphere.
    Vec2 uv(const Vec3& p) const;
    /// Unit outward normal at surface point p.
    Vec3 normal(const Vec3& p) const { return glm::normalize(p - center); }
    /// Hit point and its error bound from the ray and t, reprojected onto the surface.
    void hitPoint(const Ray& ray, float t, Vec3& p, Vec3& pError) const;
    /// Uniform point on the surface; density 1 / area.
    SurfaceSample sample(Vec2 u) const;
};

}  // namespace caustic
