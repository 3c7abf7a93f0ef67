#include "materials/dielectric.h"

#include "materials/fresnel.h"

namespace caustic {

float dielectricReflectance(FresnelModel model, float cosThetaI, float eta) {
    return model == FresnelModel::Exact ? fresnelDielectric(cosThetaI, eta)
                                        : fresnelSchlick(cosThetaI, eta);
}

float Dielectric::reflectance(const Vec3& wo, const Vec3& n) const {
    return dielectricReflectance(fresnel_, glm::dot(wo, n), ior_);
}

int Dielectric::specularLobes(const Vec3& wo, const Vec3& n, TransportMode mode,
                              SpecularLobe out[2]) const {
    float r = reflectance(wo, n);
    int count = 0;
    if (r > 0.0f) out[count++] = SpecularLobe{reflect(wo, n), r * tint_};
    float etaPath = 1.0f;
    Vec3 wt;
    if (r < 1.0f && refract(wo, n, ior_, etaPath, wt)) {
        Color t = (1.0f - r) * tint_;
        // Radiance is compressed into a smaller solid angle on entering a denser medium.
        if (mode == TransportMode::Radiance) t /= sqr(etaPath);
        out[count++] = SpecularLobe{wt, t};
    }
    return count;
}

std::optional<BsdfSample> Dielectric::sample(const Vec3& wo, const Vec3& n, float uc, Vec2,
                                             TransportMode mode) const {
    SpecularLobe lobes[2];
    int count = specularLobes(wo, n, mode, lobes);
    if (count == 0) return std::nullopt;
    float r = reflectance(wo, n);
    // Pick reflection with probability R when both lobes exist; otherwise the only one.
    int pick = 0;
    float prob = 1.0f;
    if (count == 2) {
        pick = uc < r ? 0 : 1;
        prob = pick == 0 ? r : 1.0f - r;
    }
    std::optional<BsdfSample> s = specularSample(lobes[pick], n, prob);
    // Transmitted when wi leaves on the far side of wo.
    if (s && glm::dot(s->wi, n) * glm::dot(wo, n) < 0.0f)
        s->eta = glm::dot(wo, n) > 0.0f ? ior_ : 1.0f / ior_;
    return s;
}

}  // namespace caustic
