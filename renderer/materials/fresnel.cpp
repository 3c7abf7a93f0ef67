#include "materials/fresnel.h"

namespace caustic {

float fresnelDielectric(float cosThetaI, float eta) {
    cosThetaI = std::clamp(cosThetaI, -1.0f, 1.0f);
    if (cosThetaI < 0.0f) {
        eta = 1.0f / eta;
        cosThetaI = -cosThetaI;
    }
    float sin2ThetaI = 1.0f - sqr(cosThetaI);
    float sin2ThetaT = sin2ThetaI / sqr(eta);
    if (sin2ThetaT >= 1.0f) return 1.0f;
    float cosThetaT = safeSqrt(1.0f - sin2ThetaT);
    float rParallel = (eta * cosThetaI - cosThetaT) / (eta * cosThetaI + cosThetaT);
    float rPerpendicular = (cosThetaI - eta * cosThetaT) / (cosThetaI + eta * cosThetaT);
    return std::clamp(0.5f * (sqr(rParallel) + sqr(rPerpendicular)), 0.0f, 1.0f);
}

float fresnelSchlick(float cosThetaI, float eta) {
    cosThetaI = std::clamp(cosThetaI, -1.0f, 1.0f);
    if (cosThetaI < 0.0f) {
        eta = 1.0f / eta;
        cosThetaI = -cosThetaI;
    }
    float r0 = sqr((eta - 1.0f) / (eta + 1.0f));
    float cosine = cosThetaI;
    if (eta < 1.0f) {
        // Leaving the denser medium: Schlick's form holds in the transmitted angle.
        float sin2ThetaT = (1.0f - sqr(cosThetaI)) / sqr(eta);
        if (sin2ThetaT >= 1.0f) return 1.0f;
        cosine = safeSqrt(1.0f - sin2ThetaT);
    }
    float m = 1.0f - cosine;
    return r0 + (1.0f - r0) * (m * m) * (m * m) * m;
}

bool refract(const Vec3& wi, Vec3 n, float eta, float& etaPath, Vec3& wt) {
    float cosThetaI = glm::dot(n, wi);
    if (cosThetaI < 0.0f) {
        eta = 1.0f / eta;
        cosThetaI = -cosThetaI;
        n = -n;
    }
    float sin2ThetaI = std::max(0.0f, 1.0f - sqr(cosThetaI));
    float sin2ThetaT = sin2ThetaI / sqr(eta);
    if (sin2ThetaT >= 1.0f) return false;
    float cosThetaT = safeSqrt(1.0f - sin2ThetaT);
    wt = glm::normalize(-wi / eta + (cosThetaI / eta - cosThetaT) * n);
    etaPath = eta;
    return true;
}

}  // namespace caustic
