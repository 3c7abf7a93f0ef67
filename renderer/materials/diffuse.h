// Lambertian reflection: f = albedo / pi on the side wo lies on.
#pragma once

#include "materials/material.h"

namespace caustic {

class Diffuse final : public Material {
public:
    Diffuse(const Color& albedo, const Color& emission)
        : Material(emission, false), albedo_(albedo) {}

    Color f(const Vec3& wo, const Vec3& wi, const Vec3& n) const override;
    float pdf(const Vec3& wo, const Vec3& wi, const Vec3& n) const override;
    std::optional<BsdfSample> sample(const Vec3& wo, const Vec3& n, float uc, Vec2 u,
                                     TransportMode mode) const override;
    int specularLobes(const Vec3&, const Vec3&, TransportMode, SpecularLobe[2]) const override {
        return 0;
    }
    /// The weight is the albedo (cosine-weighted sampling, diffuse.cpp).
    float maxScatterWeight() const override { return maxComponent(albedo_); }
    std::optional<Color> lambertian() const override { return albedo_ * kInvPi; }
    const Color& albedo() const { return albedo_; }

private:
    Color albedo_;
};

}  // namespace caustic
