// Fresnel reflectance of a dielectric interface and the directions of reflection and refraction.
// Conventions as pbrt-v4 (section 9.3): eta = eta_t / eta_i, the index of refraction of the side
// the normal points away from over that of the side it points to; directions point away from the
// surface.
#pragma once

#include "core/math.h"

namespace caustic {

/// Unpolarized Fresnel reflectance of a dielectric interface, the mean of the squared s- and
/// p-polarized amplitude ratios (Hecht, Optics, 4.6.2). cosThetaI = dot(n, wi), where wi lies on
/// the side n points to when positive; a negative value means the ray arrives from the other side,
/// and the interface is evaluated with 1/eta. Returns 1 under total internal reflection. In [0, 1].
/// Thread-safe, pure.
float fresnelDielectric(float cosThetaI, float eta);

/// Schlick's approximation R0 + (1 - R0)(1 - cos)^5 with R0 = ((eta - 1)/(eta + 1))^2 (Schlick
/// 1994, "An Inexpensive BRDF Model for Physically-based Rendering", eq. 24). From the denser side
/// it uses the cosine of the transmitted angle, and returns 1 under total internal reflection.
float fresnelSchlick(float cosThetaI, float eta);

/// Mirror reflection of wo about n.
inline Vec3 reflect(const Vec3& wo, const Vec3& n) {
    return -wo + 2.0f * glm::dot(wo, n) * n;
}

/// Refraction of wi through the interface with normal n and relative index eta (Snell's law,
/// pbrt-v4 eq. 9.4). wi points away from the surface. On success writes the unit transmitted
/// direction and the relative index along the path, etaPath (eta when wi is on n's side, 1/eta
/// otherwise), and returns true; returns false under total internal reflection.
bool refract(const Vec3& wi, Vec3 n, float eta, float& etaPath, Vec3& wt);

}  // namespace caustic
