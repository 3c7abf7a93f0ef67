#include "materials/ggx_albedo.h"

#include <algorithm>

#include "materials/ggx.h"

namespace caustic {
namespace {

// The smallest width tabulated: a roughness of 0.01. Narrower lobes keep all their energy.
constexpr float kMinAlpha = 1e-4f;

// A fractional index into n nodes evenly spaced on [0, 1]: the node below and the weight above.
// x outside [0, 1] is clamped, and NaN taken as 0 (converting a NaN to int is undefined).
void locate(float x, int n, int& i, float& t) {
    const float f = (x > 0.0f ? std::min(x, 1.0f) : 0.0f) * float(n - 1);
    i = std::min(int(f), n - 2);
    t = f - float(i);
}

}  // namespace

const GgxAlbedo& GgxAlbedo::get() {
    static const GgxAlbedo table;
    return table;
}

GgxAlbedo::GgxAlbedo() {
    // With Fresnel 1 and visible-normal sampling, f cos / pdf is G(wo, wi) / G1(wo) for a
    // reflection above the horizon (Heitz 2018, eq. 19), so E is its mean over the visible normals.
    // GGX's tail is long (a fraction alpha^2 / (1 + alpha^2) of the normals seen head-on lie beyond
    // 45 degrees, and reflect below the horizon), and it lies at u.y near 1: the midpoint rule runs
    // in t, with u.y = 1 - (1 - t)^4, whose points crowd there.
    constexpr int strataPhi = 16, strataT = 256;
#pragma omp parallel for schedule(dynamic)
    for (int j = 0; j < kRoughness; ++j) {
        const float r = float(j) / float(kRoughness - 1);
        const float alpha = std::max(Ggx::alphaOf(r), kMinAlpha);
        const Ggx ggx(alpha, alpha);
        for (int i = 0; i < kMu; ++i) {
            const float mu = std::max(float(i) / float(kMu - 1), 1e-4f);
            const Vec3 wo(safeSqrt(1.0f - mu * mu), 0.0f, mu);
            double sum = 0.0, schlick = 0.0;
            for (int b = 0; b < strataT; ++b) {
                const double t = (b + 0.5) / strataT, rest = 1.0 - t;
                const double uy = 1.0 - rest * rest * rest * rest,
                             jacobian = 4.0 * rest * rest * rest;
                for (int a = 0; a < strataPhi; ++a) {
                    const Vec2 u((float(a) + 0.5f) / strataPhi, float(uy));
                    const Vec3 wm = ggx.sampleVisible(wo, u);
                    const Vec3 wi = 2.0f * glm::dot(wo, wm) * wm - wo;
                    if (!(wi.z > 0.0f)) continue;
                    const double e = jacobian * ggx.G(wo, wi) / ggx.G1(wo);
                    const double w = 1.0 - std::clamp(double(glm::dot(wo, wm)), 0.0, 1.0);
                    sum += e;
                    schlick += e * (w * w) * (w * w) * w;
                }
            }
            const size_t at = size_t(j * kMu + i);
            one_.albedo[at] = std::min(1.0f, float(sum / (strataPhi * strataT)));
            schlick_.albedo[at] = std::min(1.0f, float(schlick / (strataPhi * strataT)));
        }
        for (Table* table : {&one_, &schlick_}) {
            // 2 int E mu dmu, exactly for E linear between nodes: on [a, b] with h = b - a,
            // int E mu = h / 6 (E_a (2a + b) + E_b (a + 2b)).
            const float h = 1.0f / float(kMu - 1);
            double avg = 0.0;
            for (int i = 0; i + 1 < kMu; ++i) {
                const float a = float(i) * h, b = a + h;
                avg += h / 6.0 *
                       (table->albedo[size_t(j * kMu + i)] * (2.0 * a + b) +
                        table->albedo[size_t(j * kMu + i + 1)] * (a + 2.0 * b));
            }
            table->average[size_t(j)] = float(2.0 * avg);
        }
    }
}

float GgxAlbedo::albedo(float mu, float roughness) const {
    return one_.at(mu, roughness);
}

float GgxAlbedo::average(float roughness) const {
    return one_.averageAt(roughness);
}

float GgxAlbedo::schlickAlbedo(float mu, float roughness) const {
    return schlick_.at(mu, roughness);
}

float GgxAlbedo::schlickAverage(float roughness) const {
    return schlick_.averageAt(roughness);
}

float GgxAlbedo::Table::at(float mu, float roughness) const {
    int i, j;
    float s, t;
    locate(mu, kMu, i, s);
    locate(roughness, kRoughness, j, t);
    auto node = [&](int jj, int ii) { return albedo[size_t(jj * kMu + ii)]; };
    const float lo = (1.0f - s) * node(j, i) + s * node(j, i + 1);
    const float hi = (1.0f - s) * node(j + 1, i) + s * node(j + 1, i + 1);
    return (1.0f - t) * lo + t * hi;
}

float GgxAlbedo::Table::averageAt(float roughness) const {
    int j;
    float t;
    locate(roughness, kRoughness, j, t);
    return (1.0f - t) * average[size_t(j)] + t * average[size_t(j + 1)];
}

}  // namespace caustic
