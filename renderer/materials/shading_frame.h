// An orthonormal frame around a surface normal, for BSDFs written in local coordinates: z is the
// normal, x and y its tangents (coordinateSystem's, so the frame of a normal is always the same).
#pragma once

#include "core/math.h"

namespace caustic {

struct ShadingFrame {
    Vec3 t, b, n;
    /// n: a unit normal.
    explicit ShadingFrame(const Vec3& normal) : n(normal) { coordinateSystem(n, t, b); }
    Vec3 toLocal(const Vec3& v) const {
        return Vec3(glm::dot(v, t), glm::dot(v, b), glm::dot(v, n));
    }
    Vec3 toWorld(const Vec3& v) const { return v.x * t + v.y * b + v.z * n; }
};

}  // namespace caustic
