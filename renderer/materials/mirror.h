// A perfect mirror: reflects wo about the normal, scaled by `reflectance`.
#pragma once

#include "materials/material.h"

namespace caustic {

class Mirror final : public Material {
public:
    Mirror(const Color& reflectance, const Color& emission)
        : Material(emission, true), reflectance_(reflectance) {}

    Color f(const Vec3&, const Vec3&, const Vec3&) const override { return Color(0.0f); }
    float pdf(const Vec3&, const Vec3&, const Vec3&) const override { return 0.0f; }
    std::optional<BsdfSample> sample(const Vec3& wo, const Vec3& n, float uc, Vec2 u,
                                     TransportMode mode) const override;
    int specularLobes(const Vec3& wo, const Vec3& n, TransportMode mode,
                      SpecularLobe out[2]) const override;

private:
    Color reflectance_;
};

}  // namespace caustic
