// Vector math on GLM, the few scalar helpers the renderer needs, and floating-point error bounds.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

namespace caustic {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using DVec3 = glm::dvec3;
/// Linear RGB radiance, irradiance or reflectance.
using Color = glm::vec3;

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

/// Degrees to radians.
inline constexpr float radians(float degrees) {
    return degrees * (kPi / 180.0f);
}
inline Vec3 radians(const Vec3& degrees) {
    return degrees * (kPi / 180.0f);
}

inline float sqr(float x) {
    return x * x;
}
inline float safeSqrt(float x) {
    return std::sqrt(std::max(0.0f, x));
}
inline float luminance(const Color& c) {
    return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}
inline bool isFinite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
inline bool isFinite(const Vec2& v) {
    return std::isfinite(v.x) && std::isfinite(v.y);
}
inline bool isBlack(const Color& c) {
    return c.r == 0.0f && c.g == 0.0f && c.b == 0.0f;
}
inline float maxComponent(const Vec3& v) {
    return std::max(v.x, std::max(v.y, v.z));
}
/// Component i (0, 1 or 2) of v by one indexed load. glm's operator[] is a switch on i: a branch
/// that mispredicts wherever i changes from call to call, as a kd-tree node's axis does. (Reading
/// the bytes of a trivially copyable object is defined; x, y, z are adjacent floats.)
inline float component(const Vec3& v, int i) {
    static_assert(sizeof(Vec3) == 3 * sizeof(float) && std::is_trivially_copyable_v<Vec3>);
    float c;
    std::memcpy(&c, reinterpret_cast<const unsigned char*>(&v) + sizeof(float) * size_t(i),
                sizeof c);
    return c;
}
/// Sets component i (0, 1 or 2) of v by one indexed store, for the same reason.
inline void setComponent(Vec3& v, int i, float c) {
    std::memcpy(reinterpret_cast<unsigned char*>(&v) + sizeof(float) * size_t(i), &c, sizeof c);
}

/// Bound on the relative error of n chained float operations: gamma(n) = n u / (1 - n u), with
/// u = 2^-24 the unit roundoff (pbrt-v4, section 6.8.1).
inline constexpr float gamma(int n) {
    constexpr float u = std::numeric_limits<float>::epsilon() * 0.5f;
    return (static_cast<float>(n) * u) / (1.0f - static_cast<float>(n) * u);
}

/// The next float above v (towards +infinity), and below it; used to round offsets outwards.
inline float nextFloatUp(float v) {
    if (std::isinf(v) && v > 0.0f) return v;
    if (v == -0.0f) v = 0.0f;
    uint32_t bits = std::bit_cast<uint32_t>(v);
    bits = v >= 0.0f ? bits + 1 : bits - 1;
    return std::bit_cast<float>(bits);
}
inline float nextFloatDown(float v) {
    if (std::isinf(v) && v < 0.0f) return v;
    if (v == 0.0f) v = -0.0f;
    uint32_t bits = std::bit_cast<uint32_t>(v);
    bits = v > 0.0f ? bits - 1 : bits + 1;
    return std::bit_cast<float>(bits);
}

/// Builds an orthonormal basis (t, b) around the unit vector n (Duff et al. 2017, "Building an
/// Orthonormal Basis, Revisited", JCGT 6(1)).
inline void coordinateSystem(const Vec3& n, Vec3& t, Vec3& b) {
    float sign = std::copysign(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float c = n.x * n.y * a;
    t = Vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
    b = Vec3(c, sign + n.y * n.y * a, -n.y);
}

}  // namespace caustic
