#include "materials/conductor_fresnel.h"

namespace caustic {

Color fresnelConductor(float cosThetaI, const Color& eta, const Color& k) {
    const float cos2 = sqr(std::clamp(cosThetaI, 0.0f, 1.0f)), sin2 = 1.0f - cos2;
    Color r;
    for (int c = 0; c < 3; ++c) {
        const float eta2 = sqr(eta[c]), k2 = sqr(k[c]);
        const float t0 = eta2 - k2 - sin2;
        const float a2b2 = std::sqrt(t0 * t0 + 4.0f * eta2 * k2);
        const float t1 = a2b2 + cos2;
        const float a = safeSqrt(0.5f * (a2b2 + t0));
        const float t2 = 2.0f * std::sqrt(cos2) * a;
        const float rs = (t1 - t2) / (t1 + t2);
        const float t3 = cos2 * a2b2 + sin2 * sin2;
        const float t4 = t2 * sin2;
        const float rp = rs * (t3 - t4) / (t3 + t4);
        r[c] = std::clamp(0.5f * (rp + rs), 0.0f, 1.0f);
    }
    return r;
}

Color fresnelSchlickF0(float cosThetaI, const Color& f0) {
    const float m = 1.0f - std::clamp(cosThetaI, 0.0f, 1.0f);
    const float m5 = (m * m) * (m * m) * m;
    return f0 + (Color(1.0f) - f0) * m5;
}

ConductorFresnel ConductorFresnel::fromF0(const Color& f0) {
    ConductorFresnel f;
    f.f0_ = f0;
    // 2 int_0^1 (F0 + (1 - F0)(1 - mu)^5) mu dmu = F0 + (1 - F0) / 21.
    f.average_ = f0 + (Color(1.0f) - f0) / 21.0f;
    return f;
}

ConductorFresnel ConductorFresnel::fromComplexIor(const Color& eta, const Color& k) {
    ConductorFresnel f;
    f.schlick_ = false;
    f.eta_ = eta;
    f.k_ = k;
    // 2 int_0^1 F(mu) mu dmu by the midpoint rule; F is smooth in mu, 256 points give 1e-6.
    constexpr int n = 256;
    Color sum(0.0f);
    for (int i = 0; i < n; ++i) {
        const float mu = (float(i) + 0.5f) / float(n);
        sum += fresnelConductor(mu, eta, k) * mu;
    }
    f.average_ = 2.0f * sum / float(n);
    return f;
}

Color ConductorFresnel::operator()(float cosThetaI) const {
    return schlick_ ? fresnelSchlickF0(cosThetaI, f0_) : fresnelConductor(cosThetaI, eta_, k_);
}

}  // namespace caustic
