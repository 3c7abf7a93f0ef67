// An orthonormal frame around a surface normal, for BSDFs written in local coordinates: z is the
// normal, x and y its tangents (coordinateSystem's, so the frame of a normal is always the same).
#pragma once

#include <optional>

#include "core/math.h"
#include "materials/material.h"

namespace caustic {

struct ShadingFrame {
    Vec3 t, b, n;
    /// n: a unit normal.
    explicit ShadingFrame(const Vec3& normal) : n(normal) { coordinateSystem(n, t, b); }
    Vec3 toLocal(const Vec3& v) const {
        return Vec3(glm::dot(v, t), glm::dot(v, b), glm::dot(v, n));
    }
    Vec3 toWorld(const Vec3& v) const { return v.x * t + v.y * b + v.z * n; }
    /// The frame of the side of the surface wo lies on, for a BSDF that reflects from both sides.
    static ShadingFrame facing(const Vec3& wo, const Vec3& normal) {
        return ShadingFrame(glm::dot(wo, normal) < 0.0f ? -normal : normal);
    }
};

/// The sample of a reflection lobe at wiLocal (wiLocal.z > 0) from its evaluation there in `frame`
/// (f and pdf together): nullopt when its density is zero.
inline std::optional<BsdfSample> reflectionSample(const ShadingFrame& frame, const Vec3& wiLocal,
                                                  const BsdfEval& e) {
    if (!(e.pdf > 0.0f)) return std::nullopt;
    BsdfSample s;
    s.f = e.f;
    s.pdf = e.pdf;
    s.wi = frame.toWorld(wiLocal);
    s.weight = s.f * wiLocal.z / s.pdf;
    return s;
}

}  // namespace caustic
