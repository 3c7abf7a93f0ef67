// Warping uniform samples in [0,1)^2 to directions and points, with their densities.
#pragma once

#include "core/math.h"

namespace caustic {

/// Cosine-weighted direction on the hemisphere around +z (Malley's method, pbrt-v4 A.5.3);
/// density cos(theta) / pi per steradian.
Vec3 sampleCosineHemisphere(Vec2 u);
inline float cosineHemispherePdf(float cosTheta) {
    return std::max(cosTheta, 0.0f) * kInvPi;
}

/// Uniform direction on the unit sphere; density 1 / (4 pi).
Vec3 sampleUniformSphere(Vec2 u);
inline constexpr float kUniformSpherePdf = 1.0f / (4.0f * kPi);

/// Uniform point in the unit disk by the concentric mapping (Shirley & Chiu 1997).
Vec2 sampleConcentricDisk(Vec2 u);

/// Uniform barycentrics (b0, b1) on a triangle (Heitz 2019, "A Low-Distortion Map Between Triangle
/// and Square"); b2 = 1 - b0 - b1.
Vec2 sampleUniformTriangle(Vec2 u);

/// The power heuristic (beta = 2) weight of a strategy of density f against one of density g, one
/// sample each (Veach 1997, eq. 9.13). Written as a ratio so that huge densities give 0 or 1, never
/// the NaN of inf / inf.
inline float powerHeuristic(float f, float g) {
    if (std::isinf(f)) return std::isinf(g) ? 0.5f : 1.0f;
    if (f >= g) {
        if (!(f > 0.0f)) return 0.0f;
        float r = g / f;
        return 1.0f / (1.0f + r * r);
    }
    float r = f / g;
    return r * r / (1.0f + r * r);
}

/// Maps a vector given in the frame (t, b, n) to world space.
inline Vec3 fromLocal(const Vec3& v, const Vec3& n) {
    Vec3 t, b;
    coordinateSystem(n, t, b);
    return v.x * t + v.y * b + v.z * n;
}

}  // namespace caustic
