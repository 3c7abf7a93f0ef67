// Spheres: intersection with a precision-aware quadratic, reprojected hit points, area sampling.
#pragma once

#include <optional>

#include "core/bounds.h"
#include "core/ray.h"
#include "geometry/hit.h"

namespace caustic {

/// A sphere's front side is its outside, unless `flipped` (an emitter that lights its inside, as in
/// the furnace test; Mitsuba's flip_normals).
struct Sphere {
    Vec3 center;
    float radius;
    bool flipped = false;

    Bounds3 bounds() const {
        Bounds3 b;
        b.extend(center - Vec3(radius));
        b.extend(center + Vec3(radius));
        return b;
    }
    float area() const { return 4.0f * kPi * radius * radius; }

    /// Nearest hit distance in (0, tMax).
    std::optional<float> intersect(const Ray& ray, float tMax) const;
    /// Surface parameters (phi / 2pi, theta / pi) of a point on the sphere.
    Vec2 uv(const Vec3& p) const;
    /// Unit front-side normal at surface point p.
    Vec3 normal(const Vec3& p) const {
        Vec3 n = glm::normalize(p - center);
        return flipped ? -n : n;
    }
    /// Hit point and its error bound from the ray and t, reprojected onto the surface.
    void hitPoint(const Ray& ray, float t, Vec3& p, Vec3& pError) const;
    /// Uniform point on the surface; density 1 / area.
    SurfaceSample sample(Vec2 u) const;

    /// Samples a point of the sphere visible from `ref` uniformly in the cone of directions it
    /// subtends (pbrt-v4 6.2.4); nullopt when ref is inside or on the sphere (sample by area then).
    /// `pdf` is the solid-angle density.
    std::optional<SurfaceSample> sampleCone(const Vec3& ref, Vec2 u, float& pdf) const;
    /// The solid-angle density of sampleCone from ref, or zero when ref is inside or on the sphere.
    float coneSolidAnglePdf(const Vec3& ref) const;
};

}  // namespace caustic
