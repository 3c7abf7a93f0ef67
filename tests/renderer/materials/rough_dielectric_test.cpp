// The rough dielectric: sampling against its pdf (chi-square) from both sides over a grid of
// roughness, angle and index; sample reports against f and pdf; the generalized reciprocity of
// refraction; energy: reflection and transmission together never exceed what arrives.
#include "materials/rough_dielectric.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "core/rng.h"
#include "materials/fresnel.h"
#include "renderer/materials/chi2.h"
#include "renderer/materials/scattered_energy.h"

namespace caustic {
namespace {

using testing::directionAt;

RoughDielectric glass(float roughness, float ior = 1.5f) {
    return RoughDielectric(roughness, ior, FresnelModel::Exact, Color(1.0f), Color(0.0f));
}

}  // namespace

TEST(RoughDielectric, SamplingMatchesItsPdfFromBothSides) {
    const float roughnesses[] = {0.2f, 0.35f, 0.6f, 1.0f};
    const double thetas[] = {0.0, 30.0, 60.0, 85.0};
    const int tests = 4 * 4 * 2 * 2;
    const double significance = testing::chi2Significance(tests);
    for (float r : roughnesses)
        for (double theta : thetas)
            for (bool inside : {false, true})
                for (float ior : {1.5f, 1.1f}) {
                    const RoughDielectric m = glass(r, ior);
                    testing::expectSamplingMatchesPdf(
                        m, directionAt(inside ? 180.0 - theta : theta), significance,
                        "roughness " + std::to_string(r) + ", theta " + std::to_string(theta) +
                            (inside ? " inside" : "") + ", ior " + std::to_string(ior));
                }
}

TEST(RoughDielectric, SamplesReportTheirValueDensityAndIndex) {
    Rng rng(3);
    for (float r : {0.1f, 0.5f, 1.0f})
        for (const auto& [wo, s] :
             testing::expectSamplesReportValueAndDensity(glass(r), rng, 4000, 179.0)) {
            const bool transmitted = s.wi.z * wo.z < 0.0f;
            EXPECT_EQ(s.eta, transmitted ? (wo.z > 0.0f ? 1.5f : 1.0f / 1.5f) : 1.0f);
        }
}

// Reflection is symmetric; refraction symmetric up to the squared relative index (Veach 1997,
// eq. 5.16): without radiance's 1 / eta^2, f(wo, wi) = eta^2 f(wi, wo) for wo outside.
TEST(RoughDielectric, ReciprocityOfReflectionAndRefraction) {
    Rng rng(5);
    const float ior = 1.5f;
    const RoughDielectric m = glass(0.4f, ior);
    // Float rounding of the half vector moves values in the lobes' far tails by up to 1%, where
    // the refracted term divides by a near-cancelling (wi.wm + wo.wm / eta)^2, and decides the
    // back-facing test of values below 1e-6: nearly all pairs agree to 1e-4, every one to 1e-2 or
    // 1e-6 (an f of 0.3 is typical here).
    int pairs = 0, close = 0;
    auto expectReciprocal = [&](float x, float y) {
        ++pairs;
        if (std::abs(x - y) <= 1e-4f * std::max(x, y) + 1e-6f) ++close;
        EXPECT_NEAR(x, y, 1e-2f * std::max(x, y) + 1e-6f);
    };
    for (int i = 0; i < 2000; ++i) {
        const Vec3 a = directionAt(89.0 * rng.uniform(), 6.28 * rng.uniform());
        const Vec3 b = directionAt(89.0 * rng.uniform(), 6.28 * rng.uniform());
        expectReciprocal(m.fLocal(a, b, TransportMode::Importance).x,
                         m.fLocal(b, a, TransportMode::Importance).x);
        const Vec3 below = -b;
        const float t = m.fLocal(a, below, TransportMode::Importance).x;
        expectReciprocal(t, ior * ior * m.fLocal(below, a, TransportMode::Importance).x);
        // Radiance carries 1 / eta^2 of the path.
        EXPECT_NEAR(m.fLocal(a, below, TransportMode::Radiance).x * ior * ior, t,
                    1e-5f * t + 1e-9f);
    }
    EXPECT_GE(close, pairs * 99 / 100) << close << " of " << pairs << " pairs within 1e-4";
}

// What scatters, reflected plus transmitted (importance: no 1 / eta^2), is at most what arrives;
// the rest, light that would bounce between microfacets, is lost (printed). A nearly smooth
// interface keeps everything and reflects its Fresnel fraction.
TEST(RoughDielectric, ConservesEnergyAndApproachesTheSmoothInterface) {
    for (float r : {0.05f, 0.25f, 0.5f, 1.0f})
        for (double theta : {0.0, 45.0, 80.0, 135.0, 170.0}) {
            const RoughDielectric m = glass(r);
            const Vec3 wo = directionAt(theta);
            const testing::ScatteredEnergy e =
                testing::scatteredEnergy(m, wo, 200000, TransportMode::Importance, 11);
            const double total = e.total.x, reflected = e.reflected.x;
            std::printf(
                "roughness %.2f, theta %3.0f: scattered %.4f (reflected %.4f; smooth %.4f)\n", r,
                theta, total, reflected, fresnelDielectric(wo.z, 1.5f));
            EXPECT_LE(total, 1.005) << "roughness " << r << ", theta " << theta;
            if (r == 0.05f) {
                EXPECT_GE(total, 0.99) << theta;
                EXPECT_NEAR(reflected, fresnelDielectric(wo.z, 1.5f), 0.01) << theta;
            }
        }
}

}  // namespace caustic
