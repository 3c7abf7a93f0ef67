#include "materials/diffuse.h"

#include "core/sampling.h"

namespace caustic {

Color Diffuse::f(const Vec3& wo, const Vec3& wi, const Vec3& n) const {
    // Two-sided: light scatters only between directions on the same side.
    if (glm::dot(wo, n) * glm::dot(wi, n) <= 0.0f) return Color(0.0f);
    return albedo_ * kInvPi;
}

float Diffuse::pdf(const Vec3& wo, const Vec3& wi, const Vec3& n) const {
    float cosO = glm::dot(wo, n), cosI = glm::dot(wi, n);
    if (cosO * cosI <= 0.0f) return 0.0f;
    return cosineHemispherePdf(std::abs(cosI));
}

std::optional<BsdfSample> Diffuse::sample(const Vec3& wo, const Vec3& n, float, Vec2 u,
                                          TransportMode) const {
    float cosO = glm::dot(wo, n);
    if (cosO == 0.0f) return std::nullopt;
    Vec3 side = cosO > 0.0f ? n : -n;
    Vec3 local = sampleCosineHemisphere(u);
    if (local.z <= 0.0f) return std::nullopt;
    BsdfSample s;
    s.wi = fromLocal(local, side);
    s.f = albedo_ * kInvPi;
    s.pdf = cosineHemispherePdf(local.z);
    s.weight = albedo_;  // (albedo/pi) cos / (cos/pi)
    return s;
}

}  // namespace caustic
