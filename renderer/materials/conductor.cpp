#include "materials/conductor.h"

#include "core/sampling.h"
#include "materials/fresnel.h"
#include "materials/shading_frame.h"

namespace caustic {

Conductor::Conductor(float roughness, const ConductorFresnel& fresnel, bool multipleScattering,
                     const Color& emission)
    : Material(emission, roughness < kSmoothRoughness),
      ggx_(Ggx::alphaOf(roughness), Ggx::alphaOf(roughness)),
      fresnel_(fresnel) {
    if (!isSpecular()) setLobeRoughness(roughness);
    if (multipleScattering && roughness >= kSmoothRoughness)
        multiple_ = MultipleScatteringLobe(roughness, fresnel_.average());
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
    if (multiple_.enabled()) {
        // The lobe is sampled by the cosine, with probability 1 - E(mu_o).
        const float lostO = multiple_.lost(wo.z);
        e.f += multiple_.f(wo.z, wi.z);
        e.pdf = (1.0f - lostO) * e.pdf + lostO * cosineHemispherePdf(wi.z);
    }
    return e;
}

Color Conductor::f(const Vec3& wo, const Vec3& wi, const Vec3& n) const {
    if (isSpecular()) return Color(0.0f);
    const ShadingFrame frame = ShadingFrame::facing(wo, n);
    return evalLocal(frame.toLocal(wo), frame.toLocal(wi)).f;
}

float Conductor::pdf(const Vec3& wo, const Vec3& wi, const Vec3& n) const {
    if (isSpecular()) return 0.0f;
    const ShadingFrame frame = ShadingFrame::facing(wo, n);
    return evalLocal(frame.toLocal(wo), frame.toLocal(wi)).pdf;
}

std::optional<BsdfSample> Conductor::sample(const Vec3& wo, const Vec3& n, float uc, Vec2 u,
                                            TransportMode mode) const {
    if (isSpecular()) {
        SpecularLobe lobe;
        if (specularLobes(wo, n, mode, &lobe) == 0) return std::nullopt;
        return specularSample(lobe, n);
    }
    const ShadingFrame frame = ShadingFrame::facing(wo, n);
    const Vec3 woLocal = frame.toLocal(wo);
    if (!(woLocal.z > 0.0f)) return std::nullopt;
    Vec3 wiLocal;
    // The multiple-scattering lobe with probability 1 - E(mu_o), as evalLocal's pdf says.
    if (multiple_.enabled() && uc < multiple_.lost(woLocal.z)) {
        wiLocal = sampleCosineHemisphere(u);
    } else {
        const Vec3 wm = ggx_.sampleVisible(woLocal, u);
        wiLocal = reflect(woLocal, wm);
    }
    if (!(wiLocal.z > 0.0f)) return std::nullopt;
    return reflectionSample(frame, wiLocal, evalLocal(woLocal, wiLocal));
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
