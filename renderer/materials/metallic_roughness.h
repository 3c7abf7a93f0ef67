// glTF 2.0's metallic-roughness material (its specification's Appendix B, "BRDF
// Implementation"): a dielectric, Lambertian diffuse under a GGX specular layer with Schlick's
// Fresnel term of F0 = 0.04 (ior 1.5; KHR_materials_ior sets another), and a metal, GGX reflection
// with Schlick's Fresnel from F0 = base colour, mixed by `metallic`:
//
//   f = (1 - metallic) [F_d spec + base / pi  L(mu_o) L(mu_i) / (1 - E_d,avg)]
//       + metallic [F_m spec + multiple scattering],
//   F_d = 0.04 + 0.96 (1 - v.h)^5,  F_m = base + (1 - base) (1 - v.h)^5,
//   spec = D G / (4 |n.l| |n.v|)  (GGX, alpha = roughness^2, Smith height-correlated G),
//   L(mu) = 1 - E_d(mu), E_d the directional albedo of the specular layer F_d spec.
//
// The specification weights the diffuse by (1 - F_d(v.h)); that creates light (a white dielectric
// reflects up to 1.59 times what it receives at grazing angles, measured in the tests), so the
// diffuse takes instead what the specular layer leaves in each direction, in the reciprocal form
// of Kulla and Conty 2017 (slide 26): the dielectric's albedo is E_d(mu_o) + base (1 - E_d(mu_o))
// <= 1. The metal gets Kulla and Conty's multiple-scattering lobe, so that a white rough metal in
// a white furnace stays white. Both sides reflect; the material is opaque.
#pragma once

#include "materials/ggx.h"
#include "materials/material.h"
#include "materials/multiple_scattering.h"

namespace caustic {

class MetallicRoughness final : public Material {
public:
    /// baseColor in [0, 1] per channel; metallic and roughness (perceptual) in [0, 1]. A
    /// roughness below kMinRoughness is taken as kMinRoughness: the diffuse and specular lobes
    /// share one sampler, so the specular one cannot be a delta.
    /// ior (KHR_materials_ior, >= 1) sets the dielectric's F0 = ((ior - 1) / (ior + 1))^2.
    MetallicRoughness(const Color& baseColor, float metallic, float roughness,
                      bool multipleScattering, const Color& emission, float ior = 1.5f);

    Color f(const Vec3& wo, const Vec3& wi, const Vec3& n) const override;
    float pdf(const Vec3& wo, const Vec3& wi, const Vec3& n) const override;
    /// A visible normal's mirror direction, or a cosine-weighted direction (for the diffuse and
    /// multiple-scattering lobes), chosen by their estimated shares of the albedo from wo.
    std::optional<BsdfSample> sample(const Vec3& wo, const Vec3& n, float uc, Vec2 u,
                                     TransportMode mode) const override;
    int specularLobes(const Vec3&, const Vec3&, TransportMode, SpecularLobe[2]) const override {
        return 0;
    }

    static constexpr float kMinRoughness = 0.03f;

private:
    /// The probability of sampling the specular lobe from wo (local, wo.z > 0).
    float specularProbability(float cosO) const;
    BsdfEval evalLocal(const Vec3& wo, const Vec3& wi) const;

    /// E_d(mu): the directional albedo of the dielectric's specular layer.
    float dielectricAlbedo(float mu) const;

    float f0_;  ///< The dielectric's Fresnel reflectance at normal incidence (0.04 at ior 1.5).
    Color base_;
    float metallic_;
    float roughness_;
    Ggx ggx_;
    float diffuseScale_;               ///< 1 / (pi (1 - E_d,avg))
    MultipleScatteringLobe multiple_;  ///< The metal's; off at metallic 0 or when asked.
};

}  // namespace caustic
