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

BsdfEval Conductor::evalLocal(const Vec3& wo, const Vec3& wi) const {
    if (!(wi.z > 0.0f) || !(wo.z > 0.0f)) return {};
    Vec3 wm = wo + wi;
    if (glm::dot(wm, wm) == 0.0f) return {};
    wm = glm::normalize(wm);
    BsdfEval e;
    // Single scattering: D F G / (4 cos_o cos_i) (Walter et al. 2007, eq. 20); sampled by a
    // visible normal's density through the Jacobian of reflection 1 / (4 wo.wm) (eq. 14).
    const float d = ggx_.D(wm);
    e.f = d * fresnel_(glm::dot(wo, wm)) * ggx_.G(wo, wi) / (4.0f * wo.z * wi.z);
    e.pdf = ggx_.visibleD(wo, wm) / (4.0f * glm::dot(wo, wm));
    if (multipleScattering_) {
        // (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg)): it integrates against cos_i to
        // 1 - E(mu_o), the energy single scattering lost, and is reciprocal. It is sampled by
        // the cosine, with probability 1 - E(mu_o).
        const GgxAlbedo& table = GgxAlbedo::get();
        const float lostO = 1.0f - table.albedo(wo.z, roughness_);
        const float lostI = 1.0f - table.albedo(wi.z, roughness_);
        e.f += multipleFresnel_ * (lostO * lostI / (kPi * (1.0f - averageAlbedo_)));
        e.pdf = (1.0f - lostO) * e.pdf + lostO * cosineHemispherePdf(wi.z);
    }
    return e;
}

Color Conductor::f(const Vec3& wo, const Vec3& wi, const Vec3& n) const {
    if (isSpecular()) return Color(0.0f);
    const ShadingFrame frame = sideFrame(wo, n);
    return evalLocal(frame.toLocal(wo), frame.toLocal(wi)).f;
}

float Conductor::pdf(const Vec3& wo, const Vec3& wi, const Vec3& n) const {
    if (isSpecular()) return 0.0f;
    const ShadingFrame frame = sideFrame(wo, n);
    return evalLocal(frame.toLocal(wo), frame.toLocal(wi)).pdf;
}

std::optional<BsdfSample> Conductor::sample(const Vec3& wo, const Vec3& n, float uc, Vec2 u,
                                            TransportMode mode) const {
    if (isSpecular()) {
        SpecularLobe lobe;
        if (specularLobes(wo, n, mode, &lobe) == 0) return std::nullopt;
        return specularSample(lobe, n);
    }
    const ShadingFrame frame = sideFrame(wo, n);
    const Vec3 woLocal = frame.toLocal(wo);
    if (!(woLocal.z > 0.0f)) return std::nullopt;
    Vec3 wiLocal;
    // The multiple-scattering lobe with probability 1 - E(mu_o), as evalLocal's pdf says.
    if (multipleScattering_ && uc < 1.0f - GgxAlbedo::get().albedo(woLocal.z, roughness_)) {
        wiLocal = sampleCosineHemisphere(u);
    } else {
        const Vec3 wm = ggx_.sampleVisible(woLocal, u);
        wiLocal = reflect(woLocal, wm);
    }
    if (!(wiLocal.z > 0.0f)) return std::nullopt;
    const BsdfEval e = evalLocal(woLocal, wiLocal);
    if (!(e.pdf > 0.0f)) return std::nullopt;
    BsdfSample s;
    s.f = e.f;
    s.pdf = e.pdf;
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
