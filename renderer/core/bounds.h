// Axis-aligned bounding boxes.
#pragma once

#include <cmath>
#include <cstdint>

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

/// The sphere around a scene's bounds, which lights at infinity (directional, environment) send
/// their photons in through; a unit sphere at the origin for an empty scene.
inline void sceneBoundingSphere(const Bounds3& b, Vec3& center, float& radius) {
    radius = 0.5f * std::sqrt(glm::dot(b.diagonal(), b.diagonal()));
    if (std::isfinite(radius) && radius > 0.0f) {
        center = b.center();
    } else {
        center = Vec3(0.0f);
        radius = 1.0f;
    }
}

/// Relative slack on ray parameters compared across boxes and planes: a rounding error in a plane
/// crossing must never skip a box the ray enters (pbrt-v3 3.9.2 uses 1 + 2 gamma(3) for box slabs).
constexpr float kRayBoxSlack = 2.0f * gamma(3);

/// Bit a set where direction component a is negative (its sign bit: -0 counts), for clipToBox.
inline uint32_t directionSignBits(const Vec3& d) {
    return uint32_t(std::signbit(d.x)) | uint32_t(std::signbit(d.y)) << 1 |
           uint32_t(std::signbit(d.z)) << 2;
}

/// Clips the ray's range [t0, t1] to the box; false when the ray misses it. invDir is 1 / the
/// direction, `negative` its directionSignBits. Each slab's near and far sides come from the
/// direction's sign (no comparison of the two), and the range shrinks by min and max. A NaN (a
/// zero direction component with the origin on a slab) fails both comparisons and leaves the
/// range alone.
inline bool clipToBox(const Bounds3& box, const Vec3& org, const Vec3& invDir, uint32_t negative,
                      float& t0, float& t1) {
    for (int a = 0; a < 3; ++a) {
        const float tLo = (component(box.lo, a) - component(org, a)) * component(invDir, a);
        const float tHi = (component(box.hi, a) - component(org, a)) * component(invDir, a);
        const bool flip = (negative >> a) & 1u;
        const float tNear = flip ? tHi : tLo;
        const float tFar = (flip ? tLo : tHi) * (1.0f + kRayBoxSlack);
        t0 = tNear > t0 ? tNear : t0;
        t1 = tFar < t1 ? tFar : t1;
    }
    return t0 <= t1;
}

}  // namespace caustic
