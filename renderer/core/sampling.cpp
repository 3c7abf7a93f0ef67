#include "core/sampling.h"

namespace caustic {

Vec2 sampleConcentricDisk(Vec2 u) {
    Vec2 o = 2.0f * u - Vec2(1.0f);
    if (o.x == 0.0f && o.y == 0.0f) return Vec2(0.0f);
    float r, theta;
    if (std::abs(o.x) > std::abs(o.y)) {
        r = o.x;
        theta = (kPi / 4.0f) * (o.y / o.x);
    } else {
        r = o.y;
        theta = kPi / 2.0f - (kPi / 4.0f) * (o.x / o.y);
    }
    return r * Vec2(std::cos(theta), std::sin(theta));
}

Vec3 sampleCosineHemisphere(Vec2 u) {
    Vec2 d = sampleConcentricDisk(u);
    float z = safeSqrt(1.0f - d.x * d.x - d.y * d.y);
    return Vec3(d.x, d.y, z);
}

Vec3 sampleUniformSphere(Vec2 u) {
    float z = 1.0f - 2.0f * u.x;
    float r = safeSqrt(1.0f - z * z);
    float phi = 2.0f * kPi * u.y;
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

Vec2 sampleUniformTriangle(Vec2 u) {
    float b0, b1;
    if (u.x < u.y) {
        b0 = u.x / 2.0f;
        b1 = u.y - b0;
    } else {
        b1 = u.y / 2.0f;
        b0 = u.x - b1;
    }
    return Vec2(b0, b1);
}

}  // namespace caustic
