// glTF's metallic-roughness material with its inputs read from images (glTF 2.0, "Materials"):
// base colour = factor x texture (sRGB, its alpha unused here), metallic and roughness = factors x
// the B and G channels of one linear texture, and a tangent-space normal map (linear, scaled in
// x and y by `normalScale`), and glTF's alpha: `alpha` times the base colour texture's alpha
// channel, cut out below a cutoff (mask) or passed through with probability 1 - alpha (blend). At
// each point it becomes a MetallicRoughness of the values found there (metallic_roughness.h). An
// emissive texture (sRGB) multiplies the emission.
#pragma once

#include <memory>

#include "materials/material.h"
#include "materials/material_scratch.h"
#include "textures/texture_slot.h"

namespace caustic {

enum class AlphaMode { Opaque, Mask, Blend };

class TexturedMetallicRoughness final : public Material {
public:
    struct Inputs {
        Color baseColor{1.0f};
        float metallic = 1.0f, roughness = 1.0f;
        bool multipleScattering = true;
        Color emission{0.0f};
        TextureSlot baseColorTexture, metallicRoughnessTexture, normalTexture, emissiveTexture;
        float normalScale = 1.0f;
        AlphaMode alphaMode = AlphaMode::Opaque;
        float alpha = 1.0f;        ///< glTF's baseColorFactor[3]
        float alphaCutoff = 0.5f;  ///< For Mask.
        float ior = 1.5f;          ///< KHR_materials_ior: the dielectric's F0.
    };
    /// `store` holds the slots' images and outlives the material; it may be null when no slot has
    /// an image (a scene loaded only to be admitted).
    TexturedMetallicRoughness(const Inputs& inputs, std::shared_ptr<const TextureStore> store);

    const Material& atPoint(const TexturePoint& point, Vec3& ns,
                            MaterialScratch& scratch) const override;
    bool needsTangents() const override { return in_.normalTexture.named; }
    bool cutOut(const TexturePoint& point, float u) const override;
    Color emissionAt(const TexturePoint& point) const override;
    Color averageEmission() const override;

    // Off a point (where nothing calls atPoint): the material of the factors alone.
    Color f(const Vec3& wo, const Vec3& wi, const Vec3& n) const override {
        return factors_.f(wo, wi, n);
    }
    float pdf(const Vec3& wo, const Vec3& wi, const Vec3& n) const override {
        return factors_.pdf(wo, wi, n);
    }
    std::optional<BsdfSample> sample(const Vec3& wo, const Vec3& n, float uc, Vec2 u,
                                     TransportMode mode) const override {
        return factors_.sample(wo, n, uc, u, mode);
    }
    int specularLobes(const Vec3&, const Vec3&, TransportMode, SpecularLobe[2]) const override {
        return 0;
    }

private:
    /// The emission where the query looks.
    Color emitted(const TextureQuery& q) const;
    /// The normal map's normal at the point, on the geometric normal's side.
    Vec3 mappedNormal(const TexturePoint& point, const Vec3& ns) const;

    Inputs in_;
    std::shared_ptr<const TextureStore> store_;
    MetallicRoughness factors_;
};

}  // namespace caustic
