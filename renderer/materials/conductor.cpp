#include "materials/conductor.h"

#include "core/sampling.h"
#include "materials/fresnel.h"
#include "materials/ggx_albedo.h"
#include "materials/shading_frame.h"

namespace caustic {
namespace {

// The frame of the side of the surface wo lies on: both sides reflect.
ShadingFrame sideFrame(const Vec3& wo, const Vec3& n) {
    return ShadingFrame(glm::dot(wo, n) < 0.0f ? -n : n);
}

}  // namespace

Conductor::Conductor(float roughness, const ConductorFresnel& fresnel, bool multipleScattering,
                     const Color& emission)
    : Material(emission, roughness < kSmoothRoughness),
      roughness_(roughness),
      ggx_(Ggx::alphaOf(roughness), Ggx::alphaOf(roughness)),
      fresnel_(fresnel),
      multipleScattering_(multipleScattering && roughness >= kSmoothRoughness) {
    if (multipleScattering_) {
        averageAlbedo_ = GgxAlbedo::get().average(roughness);
        // F_ms = F_avg^2 E_avg / (1 - F_avg (1 - E_avg)): the light that leaves after any number
        // of bounces between microfacets, each losing 1 - F_avg (Kulla and Conty 2017, slide 21).
        const Color fAvg = fresnel_.average();
        multipleFresnel_ =
            fAvg * fAvg * averageAlbedo_ / (Color(1.0f) - fAvg * (1.0f - averageAlbedo_));
        if (1.0f - averageAlbedo_ < 1e-6f) multipleScattering_ = false;
    }
}

float Conductor::multipleScatteringProbability(float muO) const {
    return multipleScattering_ ? 1.0f - GgxAlbedo::get().albedo(muO, roughness_) : 0.0f;
}

Color Conductor::fLocal(const Vec3& wo, const Vec3& wi) const {
    if (!(wi.z > 0.0f) || !(wo.z > 0.0f)) return Color(0.0f);
    Vec3 wm = wo + wi;
    if (glm::dot(wm, wm) == 0.0f) return Color(0.0f);
    wm = glm::normalize(wm);
    // Single scattering: D F G / (4 cos_o cos_i) (Walter et al. 2007, eq. 20).
    Color f = ggx_.D(wm) * fresnel_(glm::dot(wo, wm)) * ggx_.G(wo, wi) / (4.0f * wo.z * wi.z);
    if (multipleScattering_) {
        // (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg)): it integrates against cos_i to
        // 1 - E(mu_o), the energy single scattering lost, and is reciprocal.
        const GgxAlbedo& table = GgxAlbedo::get();
        const float lost = (1.0f - table.albedo(wo.z, roughness_)) *
                           (1.0f - table.albedo(wi.z, roughness_)) /
                           (kPi * (1.0f - averageAlbedo_));
        f += multipleFresnel_ * lost;
    }
    return f;
}

float Conductor::pdfLocal(const Vec3& wo, const Vec3& wi) const {
    if (!(wi.z > 0.0f) || !(wo.z > 0.0f)) return 0.0f;
    Vec3 wm = wo + wi;
    if (glm::dot(wm, wm) == 0.0f) return 0.0f;
    wm = glm::normalize(wm);
    // A visible normal's density, through the Jacobian of reflection 1 / (4 wo.wm) (Walter et al.
    // 2007, eq. 14).
    const float pMs = multipleScatteringProbability(wo.z);
    const float single = ggx_.visibleD(wo, wm) / (4.0f * glm::dot(wo, wm));
    return (1.0f - pMs) * single + pMs * cosineHemispherePdf(wi.z);
}

Color Conductor::f(const Vec3& wo, const Vec3& wi, const Vec3& n) const {
    if (isSpecular()) return Color(0.0f);
    const ShadingFrame frame = sideFrame(wo, n);
    return fLocal(frame.toLocal(wo), frame.toLocal(wi));
}

float Conductor::pdf(const Vec3& wo, const Vec3& wi, const Vec3& n) const {
    if (isSpecular()) return 0.0f;
    const ShadingFrame frame = sideFrame(wo, n);
    return pdfLocal(frame.toLocal(wo), frame.toLocal(wi));
}

std::optional<BsdfSample> Conductor::sample(const Vec3& wo, const Vec3& n, float uc, Vec2 u,
                                            TransportMode mode) const {
    if (isSpecular()) {
        SpecularLobe lobe;
        if (specularLobes(wo, n, mode, &lobe) == 0) return std::nullopt;
        const float cosI = std::abs(glm::dot(lobe.wi, n));
        if (cosI == 0.0f) return std::nullopt;
        BsdfSample s;
        s.wi = lobe.wi;
        s.f = lobe.weight / cosI;
        s.pdf = 1.0f;
        s.weight = lobe.weight;
        s.specular = true;
        return s;
    }
    const ShadingFrame frame = sideFrame(wo, n);
    const Vec3 woLocal = frame.toLocal(wo);
    if (!(woLocal.z > 0.0f)) return std::nullopt;
    Vec3 wiLocal;
    if (uc < multipleScatteringProbability(woLocal.z)) {
        wiLocal = sampleCosineHemisphere(u);
    } else {
        const Vec3 wm = ggx_.sampleVisible(woLocal, u);
        wiLocal = reflect(woLocal, wm);
    }
    if (!(wiLocal.z > 0.0f)) return std::nullopt;
    BsdfSample s;
    s.f = fLocal(woLocal, wiLocal);
    s.pdf = pdfLocal(woLocal, wiLocal);
    if (!(s.pdf > 0.0f)) return std::nullopt;
    s.wi = frame.toWorld(wiLocal);
    s.weight = s.f * wiLocal.z / s.pdf;
    return s;
}

int Conductor::specularLobes(const Vec3& wo, const Vec3& n, TransportMode,
                             SpecularLobe out[2]) const {
    if (!isSpecular()) return 0;
    const float cosO = glm::dot(wo, n);
    if (cosO == 0.0f) return 0;
    out[0] = SpecularLobe{reflect(wo, n), fresnel_(std::abs(cosO))};
    return 1;
}

}  // namespace caustic
