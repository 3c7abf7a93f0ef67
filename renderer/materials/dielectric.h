// A smooth dielectric interface (glass, water): Fresnel-weighted specular reflection and
// refraction. The inside is the side opposite the normal; `ior` is the inside's index over the
// outside's.
#pragma once

#include "materials/material.h"

namespace caustic {

enum class FresnelModel { Exact, Schlick };

/// The reflectance of an interface of relative index eta at cosThetaI under `model`
/// (materials/fresnel.h's conventions: negative from the inside).
float dielectricReflectance(FresnelModel model, float cosThetaI, float eta);

class Dielectric final : public Material {
public:
    Dielectric(float ior, FresnelModel fresnel, const Color& tint, const Color& emission)
        : Material(emission, true), ior_(ior), fresnel_(fresnel), tint_(tint) {}

    Color f(const Vec3&, const Vec3&, const Vec3&) const override { return Color(0.0f); }
    float pdf(const Vec3&, const Vec3&, const Vec3&) const override { return 0.0f; }
    /// Chooses reflection with probability R (Fresnel), else refraction.
    std::optional<BsdfSample> sample(const Vec3& wo, const Vec3& n, float uc, Vec2 u,
                                     TransportMode mode) const override;
    int specularLobes(const Vec3& wo, const Vec3& n, TransportMode mode,
                      SpecularLobe out[2]) const override;

    /// Fresnel reflectance for wo under this material's model.
    float reflectance(const Vec3& wo, const Vec3& n) const;
    float ior() const { return ior_; }

private:
    float ior_;
    FresnelModel fresnel_;
    Color tint_;
};

}  // namespace caustic
