// A linear mix of two materials' BSDFs, f = (1 - w) f_a + w f_b: glTF's transmission
// (KHR_materials_transmission) is a metallic-roughness surface mixed with a rough dielectric
// whose weight is (1 - metallic) x transmission. Sampling picks a component by its weight and
// reports the mix's value and density for the direction, as pbrt-v3's BSDF::Sample_f does, so
// that MIS sees the whole BSDF.
#pragma once

#include <memory>

#include "materials/material.h"

namespace caustic {

class MixedMaterial final : public Material {
public:
    /// weightB in [0, 1]; neither component may be specular. Emission is the first's.
    MixedMaterial(std::unique_ptr<Material> a, std::unique_ptr<Material> b, float weightB);

    Color f(const Vec3& wo, const Vec3& wi, const Vec3& n) const override {
        return (1.0f - w_) * a_->f(wo, wi, n) + w_ * b_->f(wo, wi, n);
    }
    float pdf(const Vec3& wo, const Vec3& wi, const Vec3& n) const override {
        return (1.0f - w_) * a_->pdf(wo, wi, n) + w_ * b_->pdf(wo, wi, n);
    }
    std::optional<BsdfSample> sample(const Vec3& wo, const Vec3& n, float uc, Vec2 u,
                                     TransportMode mode) const override;
    int specularLobes(const Vec3&, const Vec3&, TransportMode, SpecularLobe[2]) const override {
        return 0;
    }

private:
    std::unique_ptr<Material> a_, b_;
    float w_;
};

}  // namespace caustic
