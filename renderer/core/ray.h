// Rays and the robust spawning of rays from surfaces.
#pragma once

#include "core/math.h"

namespace caustic {

/// A ray o + t d. d need not be unit length, but every ray the renderer spawns has a unit d, so
/// that t is a distance in scene units.
struct Ray {
    Vec3 o;
    Vec3 d;
};

/// Offsets a surface point p with absolute error bound pError (per component) along its geometric
/// normal n, to the side that w points to, far enough that a ray leaving it cannot re-intersect the
/// surface it starts on, and rounds the result away from p (pbrt-v4, section 6.8.6). The offset
/// scales with the error bound, hence with the scene's scale and distance from the origin.
inline Vec3 offsetRayOrigin(const Vec3& p, const Vec3& pError, const Vec3& n, const Vec3& w) {
    float d = glm::dot(glm::abs(n), pError);
    Vec3 offset = d * n;
    if (glm::dot(w, n) < 0.0f) offset = -offset;
    Vec3 po = p + offset;
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0.0f)
            po[i] = nextFloatUp(po[i]);
        else if (offset[i] < 0.0f)
            po[i] = nextFloatDown(po[i]);
    }
    return po;
}

/// Fraction of a shadow ray's length left unexamined at its far end so that the ray does not hit
/// the surface its target point lies on (pbrt-v4's ShadowEpsilon).
inline constexpr float kShadowEpsilon = 1e-4f;

}  // namespace caustic
