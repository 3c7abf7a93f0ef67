// A metal: GGX microfacet reflection with a conductor's Fresnel term (Walter et al. 2007, with
// Smith's height-correlated masking, Heitz 2014), sampled by visible normals (Heitz 2018), plus
// Kulla and Conty's multiple-scattering lobe, which returns the energy single scattering loses on
// rough surfaces (a white metal in a white furnace stays white). A roughness below 0.03 is a
// smooth metal: specular reflection weighted by the Fresnel term. Opaque; both sides reflect.
#pragma once

#include "materials/conductor_fresnel.h"
#include "materials/ggx.h"
#include "materials/material.h"
#include "materials/multiple_scattering.h"

namespace caustic {

class Conductor final : public Material {
public:
    /// roughness: perceptual, in [0, 1] (alpha = roughness^2). multipleScattering: add Kulla and
    /// Conty's lobe (off only to compare with renderers that lack it).
    Conductor(float roughness, const ConductorFresnel& fresnel, bool multipleScattering,
              const Color& emission);

    Color f(const Vec3& wo, const Vec3& wi, const Vec3& n) const override;
    float pdf(const Vec3& wo, const Vec3& wi, const Vec3& n) const override;
    /// A visible normal's mirror direction, or, with probability 1 - E(mu_o), a cosine-weighted
    /// direction for the multiple-scattering lobe; nullopt when the reflection falls below the
    /// horizon.
    std::optional<BsdfSample> sample(const Vec3& wo, const Vec3& n, float uc, Vec2 u,
                                     TransportMode mode) const override;
    int specularLobes(const Vec3& wo, const Vec3& n, TransportMode mode,
                      SpecularLobe out[2]) const override;

    /// Roughness below which the surface is a specular reflector.
    static constexpr float kSmoothRoughness = 0.03f;

private:
    /// f and pdf together (they share the half vector and E(mu_o)), in the local frame of the
    /// side wo is on (wo.z > 0).
    BsdfEval evalLocal(const Vec3& wo, const Vec3& wi) const;

    Ggx ggx_;
    ConductorFresnel fresnel_;
    MultipleScatteringLobe multiple_;  ///< Off for a smooth metal or when asked.
};

}  // namespace caustic
