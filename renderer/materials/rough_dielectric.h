// A rough dielectric interface (frosted glass): GGX microfacets that reflect and refract, each
// weighted by the Fresnel term of the microfacet (Walter et al. 2007, "Microfacet Models for
// Refraction through Rough Surfaces"; pbrt-v4, section 9.7), with Smith height-correlated masking
// and visible-normal sampling. As the smooth Dielectric: the inside is the side opposite the
// normal, `ior` the inside's index over the outside's, and a tint colours both lobes. Light that
// scatters between microfacets more than once is left out: a rough dielectric loses a little
// energy (measured by its furnace test), never gains it.
#pragma once

#include "materials/dielectric.h"
#include "materials/ggx.h"
#include "materials/material.h"

namespace caustic {

class RoughDielectric final : public Material {
public:
    /// roughness: perceptual, in [Conductor::kSmoothRoughness, 1] (alpha = roughness^2).
    RoughDielectric(float roughness, float ior, FresnelModel fresnel, const Color& tint,
                    const Color& emission);

    Color f(const Vec3& wo, const Vec3& wi, const Vec3& n) const override;
    float pdf(const Vec3& wo, const Vec3& wi, const Vec3& n) const override;
    /// A visible microfacet normal, then reflection with probability F (its Fresnel term), else
    /// refraction through it; nullopt when the direction falls on the wrong side.
    std::optional<BsdfSample> sample(const Vec3& wo, const Vec3& n, float uc, Vec2 u,
                                     TransportMode mode) const override;
    int specularLobes(const Vec3&, const Vec3&, TransportMode, SpecularLobe[2]) const override {
        return 0;
    }

    /// f and the density of sampling wi from wo, together (they share the generalized half
    /// vector and its Fresnel term), in the local frame of the normal, for either transport mode
    /// (radiance is scaled by 1 / eta^2 through refraction, importance is not: Veach 1997,
    /// section 5.2).
    BsdfEval evalLocal(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
    Color fLocal(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
        return evalLocal(wo, wi, mode).f;
    }

private:
    Ggx ggx_;
    float ior_;
    FresnelModel fresnel_;
    Color tint_;
};

}  // namespace caustic
