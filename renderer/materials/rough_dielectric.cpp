#include "materials/rough_dielectric.h"

#include "materials/fresnel.h"
#include "materials/shading_frame.h"

namespace caustic {
namespace {

// The microfacet normal that scatters wo into wi, on the outside's side (z > 0), and the relative
// index along the path (1 for a reflection; eta entering, 1/eta leaving): the generalized half
// vector (Walter et al. 2007, eqs. 13 and 16). nullopt when there is none or wo or wi lies on the
// microfacet's back (pbrt-v4, "Discard backfacing microfacets").
struct HalfVector {
    Vec3 wm;
    float etaPath = 1.0f;
};
std::optional<HalfVector> halfVector(const Vec3& wo, const Vec3& wi, float eta) {
    const float cosO = wo.z, cosI = wi.z;
    if (cosO == 0.0f || cosI == 0.0f) return std::nullopt;
    HalfVector h;
    if (cosO * cosI < 0.0f) h.etaPath = cosO > 0.0f ? eta : 1.0f / eta;
    Vec3 wm = wo + h.etaPath * wi;
    if (glm::dot(wm, wm) == 0.0f) return std::nullopt;
    wm = glm::normalize(wm);
    if (wm.z < 0.0f) wm = -wm;
    if (glm::dot(wm, wi) * cosI < 0.0f || glm::dot(wm, wo) * cosO < 0.0f) return std::nullopt;
    h.wm = wm;
    return h;
}

}  // namespace

RoughDielectric::RoughDielectric(float roughness, float ior, FresnelModel fresnel,
                                 const Color& tint, const Color& emission)
    : Material(emission, false),
      ggx_(Ggx::alphaOf(roughness), Ggx::alphaOf(roughness)),
      ior_(ior),
      fresnel_(fresnel),
      tint_(tint) {
    setLobeRoughness(roughness);
}

BsdfEval RoughDielectric::evalLocal(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    const std::optional<HalfVector> h = halfVector(wo, wi, ior_);
    if (!h) return {};
    const float cosO = wo.z, cosI = wi.z;
    const float dotO = glm::dot(wo, h->wm), dotI = glm::dot(wi, h->wm);
    const float R = dielectricReflectance(fresnel_, dotO, ior_);
    const float dg = ggx_.D(h->wm) * ggx_.G(wo, wi);
    // The normals visible from wo. From inside, those are the facets whose backs face wo,
    // wo.wm < 0: as many, and as dense, as those -wo sees from outside (G1 and D depend on wo
    // only through its slope).
    const float visible = ggx_.visibleD(wo.z > 0.0f ? wo : -wo, h->wm);
    BsdfEval e;
    if (cosO * cosI > 0.0f) {
        e.f = tint_ * (dg * R / std::abs(4.0f * cosI * cosO));
        e.pdf = visible / (4.0f * std::abs(dotO)) * R;
        return e;
    }
    // Walter et al. 2007, eq. 21, with the relative index of the path; sampled through the
    // Jacobian of refraction, |wi.wm| / (wi.wm + wo.wm / eta)^2 (eq. 17).
    const float jacobianDenom = sqr(dotI + dotO / h->etaPath);
    float ft = dg * (1.0f - R) * std::abs(dotI * dotO / (jacobianDenom * cosI * cosO));
    if (mode == TransportMode::Radiance) ft /= sqr(h->etaPath);
    e.f = tint_ * ft;
    e.pdf = visible * std::abs(dotI) / jacobianDenom * (1.0f - R);
    return e;
}

Color RoughDielectric::f(const Vec3& wo, const Vec3& wi, const Vec3& n) const {
    const ShadingFrame frame(n);
    return evalLocal(frame.toLocal(wo), frame.toLocal(wi), TransportMode::Radiance).f;
}

float RoughDielectric::pdf(const Vec3& wo, const Vec3& wi, const Vec3& n) const {
    const ShadingFrame frame(n);
    return evalLocal(frame.toLocal(wo), frame.toLocal(wi), TransportMode::Radiance).pdf;
}

std::optional<BsdfSample> RoughDielectric::sample(const Vec3& wo, const Vec3& n, float uc, Vec2 u,
                                                  TransportMode mode) const {
    const ShadingFrame frame(n);
    const Vec3 woLocal = frame.toLocal(wo);
    if (woLocal.z == 0.0f) return std::nullopt;
    // A normal visible from wo (pdfLocal says why -wo's from inside), on the outside's side.
    const bool outside = woLocal.z > 0.0f;
    const Vec3 wm = ggx_.sampleVisible(outside ? woLocal : -woLocal, u);
    const float R = dielectricReflectance(fresnel_, glm::dot(woLocal, wm), ior_);
    Vec3 wiLocal;
    if (uc < R) {
        wiLocal = reflect(woLocal, wm);
        if (wiLocal.z * woLocal.z <= 0.0f) return std::nullopt;
    } else {
        float etaPath = 1.0f;
        if (!refract(woLocal, wm, ior_, etaPath, wiLocal)) return std::nullopt;
        if (wiLocal.z * woLocal.z >= 0.0f) return std::nullopt;
    }
    const BsdfEval e = evalLocal(woLocal, wiLocal, mode);
    if (!(e.pdf > 0.0f) || isBlack(e.f)) return std::nullopt;
    BsdfSample s;
    s.f = e.f;
    s.pdf = e.pdf;
    s.wi = frame.toWorld(wiLocal);
    s.weight = s.f * std::abs(wiLocal.z) / s.pdf;
    if (wiLocal.z * woLocal.z < 0.0f) s.eta = outside ? ior_ : 1.0f / ior_;
    return s;
}

}  // namespace caustic
