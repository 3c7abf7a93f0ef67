#include "materials/ggx.h"

namespace caustic {

float Ggx::D(const Vec3& wm) const {
    if (!(wm.z > 0.0f)) return 0.0f;
    // 1 / (pi ax ay cos^4 (1 + tan^2 (cos^2 phi / ax^2 + sin^2 phi / ay^2))^2), with the cosines
    // and tangent multiplied out: 1 / (pi ax ay (x^2 / ax^2 + y^2 / ay^2 + z^2)^2).
    const float t = sqr(wm.x / alphaX_) + sqr(wm.y / alphaY_) + sqr(wm.z);
    return 1.0f / (kPi * alphaX_ * alphaY_ * t * t);
}

float Ggx::lambda(const Vec3& w) const {
    const float cos2 = sqr(w.z);
    if (cos2 == 0.0f) return kInfinity;
    // alpha^2 tan^2(theta) for the direction's azimuth (Heitz 2014, eq. 86).
    const float alpha2Tan2 = (sqr(alphaX_ * w.x) + sqr(alphaY_ * w.y)) / cos2;
    return 0.5f * (std::sqrt(1.0f + alpha2Tan2) - 1.0f);
}

float Ggx::visibleD(const Vec3& w, const Vec3& wm) const {
    const float cosW = std::abs(w.z);
    if (cosW == 0.0f) return 0.0f;
    return G1(w) * std::max(0.0f, glm::dot(w, wm)) * D(wm) / cosW;
}

Vec3 Ggx::sampleVisible(const Vec3& w, Vec2 u) const {
    // Stretch to the configuration where alpha is 1: the visible normals are then those of a unit
    // hemisphere, and the halfway vectors of w and a uniform point of the spherical cap z > -w.z
    // are distributed as them (Dupuy and Benyoub 2023, listing 3).
    const Vec3 ws = glm::normalize(Vec3(w.x * alphaX_, w.y * alphaY_, w.z));
    const float phi = 2.0f * kPi * u.x;
    const float z = (1.0f - u.y) * (1.0f + ws.z) - ws.z;
    const float sinTheta = safeSqrt(1.0f - z * z);
    const Vec3 hs = Vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), z) + ws;
    // Unstretch; a normal exactly in the horizon (probability 0) is lifted to stay above it.
    Vec3 wm = glm::normalize(Vec3(hs.x * alphaX_, hs.y * alphaY_, std::max(hs.z, 1e-7f)));
    return wm;
}

}  // namespace caustic
