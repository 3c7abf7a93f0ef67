#include "materials/mixed_material.h"

#include "core/check.h"

namespace caustic {

MixedMaterial::MixedMaterial(std::unique_ptr<Material> a, std::unique_ptr<Material> b,
                             float weightB)
    : Material(a->emission(), false), a_(std::move(a)), b_(std::move(b)), w_(weightB) {
    CAUSTIC_CHECK(!a_->isSpecular() && !b_->isSpecular());
    setLobeRoughness(std::max(a_->lobeRoughness(), b_->lobeRoughness()));
}

std::optional<BsdfSample> MixedMaterial::sample(const Vec3& wo, const Vec3& n, float uc, Vec2 u,
                                                TransportMode mode) const {
    // uc chooses the component, then is stretched back to [0, 1) for the component's own choice.
    const bool pickB = uc < w_;
    const Material& chosen = pickB ? *b_ : *a_;
    const Material& other = pickB ? *a_ : *b_;
    const float wChosen = pickB ? w_ : 1.0f - w_;
    const float ucChosen = std::min(pickB ? uc / w_ : (uc - w_) / (1.0f - w_), 0x1.fffffep-1f);
    std::optional<BsdfSample> s = chosen.sample(wo, n, ucChosen, u, mode);
    if (!s) return std::nullopt;
    // The sample's own f is right for the transport mode; the other component's f() (radiance)
    // is too wherever it is not zero: both reflect alike, and only the dielectric transmits.
    const float wOther = 1.0f - wChosen;
    s->f = wChosen * s->f + wOther * other.f(wo, s->wi, n);
    s->pdf = wChosen * s->pdf + wOther * other.pdf(wo, s->wi, n);
    if (!(s->pdf > 0.0f)) return std::nullopt;
    s->weight = s->f * (std::abs(glm::dot(s->wi, n)) / s->pdf);
    return s;
}

}  // namespace caustic
