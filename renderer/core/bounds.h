// Axis-aligned bounding boxes.
#pragma once

#include "core/math.h"

namespace caustic {

struct Bounds3 {
    Vec3 lo{kInfinity};
    Vec3 hi{-kInfinity};

    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    void extend(const Vec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void extend(const Bounds3& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    Vec3 diagonal() const { return hi - lo; }
    Vec3 center() const { return 0.5f * (lo + hi); }
    float surfaceArea() const {
        if (empty()) return 0.0f;
        Vec3 d = diagonal();
        return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
    }
};

}  // namespace caustic
