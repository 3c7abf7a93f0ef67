#include "materials/fresnel.h"

namespace caustic {

namespace {

// cos^2 of the transmitted angle by Snell's law, 1 - (1 - cos^2 i) / eta^2, written so that cos^2 i
// is not lost against 1 near grazing incidence (with eta = 1 it is exactly cos^2 i). Non-positive
// under total internal reflection. Shared so that all three functions agree on when that happens.
float cos2ThetaT(float cosThetaI, float eta) {
    float eta2 = sqr(eta);
    return (sqr(cosThetaI) + (eta2 - 1.0f)) / eta2;
}

}  // namespace

float fresnelDielectric(float cosThetaI, float eta) {
    cosThetaI = std::clamp(cosThetaI, -1.0f, 1.0f);
    if (cosThetaI < 0.0f) {
        eta = 1.0f / eta;
        cosThetaI = -cosThetaI;
    }
    float cos2T = cos2ThetaT(cosThetaI, eta);
    if (cos2T <= 0.0f) return 1.0f;
    float cosThetaT = std::sqrt(cos2T);
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
        float cos2T = cos2ThetaT(cosThetaI, eta);
        if (cos2T <= 0.0f) return 1.0f;
        cosine = std::sqrt(cos2T);
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
    float cos2T = cos2ThetaT(cosThetaI, eta);
    if (cos2T <= 0.0f) return false;
    float cosThetaT = std::sqrt(cos2T);
    wt = glm::normalize(-wi / eta + (cosThetaI / eta - cosThetaT) * n);
    etaPath = eta;
    return true;
}

}  // namespace caustic
