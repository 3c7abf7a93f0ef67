#include "materials/metallic_roughness.h"

#include <algorithm>

#include "core/sampling.h"
#include "materials/conductor_fresnel.h"
#include "materials/fresnel.h"
#include "materials/ggx_albedo.h"
#include "materials/shading_frame.h"

namespace caustic {
namespace {

// Schlick's factor (1 - cos)^5.
float schlickWeight(float cosTheta) {
    const float m = 1.0f - std::clamp(cosTheta, 0.0f, 1.0f);
    return (m * m) * (m * m) * m;
}

}  // namespace

MetallicRoughness::MetallicRoughness(const Color& baseColor, float metallic, float roughness,
                                     bool multipleScattering, const Color& emission, float ior)
    : Material(emission, false),
      f0_(sqr((ior - 1.0f) / (ior + 1.0f))),
      base_(baseColor),
      metallic_(metallic),
      roughness_(std::max(roughness, kMinRoughness)),
      ggx_(Ggx::alphaOf(roughness_), Ggx::alphaOf(roughness_)) {
    // A whole metal has no diffuse lobe.
    if (metallic >= 1.0f) setLobeRoughness(roughness_);
    const GgxAlbedo& table = GgxAlbedo::get();
    const float average =
        f0_ * table.average(roughness_) + (1.0f - f0_) * table.schlickAverage(roughness_);
    diffuseScale_ = kInvPi / (1.0f - average);
    if (multipleScattering && metallic > 0.0f)
        multiple_ =
            MultipleScatteringLobe(roughness_, ConductorFresnel::fromF0(baseColor).average());
}

float MetallicRoughness::dielectricAlbedo(float mu) const {
    const GgxAlbedo& table = GgxAlbedo::get();
    return f0_ * table.albedo(mu, roughness_) + (1.0f - f0_) * table.schlickAlbedo(mu, roughness_);
}

float MetallicRoughness::specularProbability(float cosO) const {
    // Each lobe's albedo from wo.
    const GgxAlbedo& table = GgxAlbedo::get();
    const float one = table.albedo(cosO, roughness_),
                schlick = table.schlickAlbedo(cosO, roughness_);
    const float dielectric = dielectricAlbedo(cosO);
    const float metal = luminance(base_ * one + (Color(1.0f) - base_) * schlick);
    const float specular = (1.0f - metallic_) * dielectric + metallic_ * metal;
    const float cosine = (1.0f - metallic_) * (1.0f - dielectric) * luminance(base_) +
                         metallic_ * multiple_.lost(cosO);
    return specular + cosine > 0.0f ? specular / (specular + cosine) : 1.0f;
}

BsdfEval MetallicRoughness::evalLocal(const Vec3& wo, const Vec3& wi) const {
    if (!(wi.z > 0.0f) || !(wo.z > 0.0f)) return {};
    Vec3 wm = wo + wi;
    if (glm::dot(wm, wm) == 0.0f) return {};
    wm = glm::normalize(wm);
    const float cosH = glm::dot(wo, wm);
    const float w = schlickWeight(cosH);
    const float fd = f0_ + (1.0f - f0_) * w;
    const Color fm = base_ + (Color(1.0f) - base_) * w;
    const float spec = ggx_.D(wm) * ggx_.G(wo, wi) / (4.0f * wo.z * wi.z);
    BsdfEval e;
    const float diffuse =
        (1.0f - dielectricAlbedo(wo.z)) * (1.0f - dielectricAlbedo(wi.z)) * diffuseScale_;
    e.f = spec * ((1.0f - metallic_) * fd + metallic_ * fm) + (1.0f - metallic_) * diffuse * base_ +
          metallic_ * multiple_.f(wo.z, wi.z);
    const float p = specularProbability(wo.z);
    e.pdf = p * ggx_.visibleD(wo, wm) / (4.0f * cosH) + (1.0f - p) * cosineHemispherePdf(wi.z);
    return e;
}

Color MetallicRoughness::f(const Vec3& wo, const Vec3& wi, const Vec3& n) const {
    const ShadingFrame frame = ShadingFrame::facing(wo, n);
    return evalLocal(frame.toLocal(wo), frame.toLocal(wi)).f;
}

float MetallicRoughness::pdf(const Vec3& wo, const Vec3& wi, const Vec3& n) const {
    const ShadingFrame frame = ShadingFrame::facing(wo, n);
    return evalLocal(frame.toLocal(wo), frame.toLocal(wi)).pdf;
}

std::optional<BsdfSample> MetallicRoughness::sample(const Vec3& wo, const Vec3& n, float uc, Vec2 u,
                                                    TransportMode) const {
    const ShadingFrame frame = ShadingFrame::facing(wo, n);
    const Vec3 woLocal = frame.toLocal(wo);
    if (!(woLocal.z > 0.0f)) return std::nullopt;
    const Vec3 wiLocal = uc < specularProbability(woLocal.z)
                             ? reflect(woLocal, ggx_.sampleVisible(woLocal, u))
                             : sampleCosineHemisphere(u);
    if (!(wiLocal.z > 0.0f)) return std::nullopt;
    return reflectionSample(frame, wiLocal, evalLocal(woLocal, wiLocal));
}

}  // namespace caustic
