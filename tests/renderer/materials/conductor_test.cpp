// The conductor: its sampling against its pdf (chi-square) over a grid of roughness, angle and
// Fresnel term; the value and density sampling reports against f and pdf; reciprocity; a white
// furnace with and without the multiple-scattering lobe; the smooth limit.
#include "materials/conductor.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "core/rng.h"
#include "materials/fresnel.h"
#include "materials/ggx_albedo.h"
#include "renderer/materials/chi2.h"
#include "renderer/materials/scattered_energy.h"

namespace caustic {
namespace {

using testing::directionAt;
const Vec3 kNormal(0.0f, 0.0f, 1.0f);

// Gold's F0 (Lagarde and de Rousiers 2014, table 3) and copper's eta, k at 650, 550, 450 nm
// (Palik, through pbrt-v4's spectra).
const ConductorFresnel kGold = ConductorFresnel::fromF0(Color(1.0f, 0.782f, 0.344f));
const ConductorFresnel kCopper =
    ConductorFresnel::fromComplexIor(Color(0.21f, 1.12f, 1.24f), Color(4.14f, 2.59f, 2.38f));
const ConductorFresnel kWhite = ConductorFresnel::fromF0(Color(1.0f));

// The directional albedo from wo (the mean of f cos / pdf over n samples).
float albedo(const Material& m, const Vec3& wo, int n) {
    return float(testing::scatteredEnergy(m, wo, n, TransportMode::Radiance, 7).total.x);
}

}  // namespace

TEST(Conductor, SamplingMatchesItsPdf) {
    const float roughnesses[] = {0.2f, 0.35f, 0.6f, 1.0f};
    const double thetas[] = {0.0, 30.0, 60.0, 85.0};
    const int tests = 4 * 4 * 2 * 2;
    const double significance = testing::chi2Significance(tests);
    for (float r : roughnesses)
        for (double theta : thetas)
            for (const ConductorFresnel* fresnel : {&kGold, &kCopper})
                for (bool ms : {true, false}) {
                    const Conductor m(r, *fresnel, ms, Color(0.0f));
                    testing::expectSamplingMatchesPdf(
                        m, directionAt(theta), significance,
                        "roughness " + std::to_string(r) + ", theta " + std::to_string(theta) +
                            (fresnel == &kGold ? ", gold" : ", copper") +
                            (ms ? ", with" : ", without") + " multiple scattering");
                }
}

TEST(Conductor, SamplesReportTheirValueAndDensity) {
    Rng rng(3);
    for (float r : {0.1f, 0.5f, 1.0f})
        testing::expectSamplesReportValueAndDensity(Conductor(r, kCopper, true, Color(0.0f)), rng,
                                                    2000, 89.0);
}

TEST(Conductor, IsReciprocalAndReflectsFromBothSides) {
    Rng rng(5);
    testing::expectReciprocalTwoSidedReflector(Conductor(0.4f, kGold, true, Color(0.0f)), rng,
                                               1000);
}

// A white metal (F0 = 1) in a white furnace reflects all it receives once the multiple-scattering
// lobe returns what single scattering loses; without it, rough metals darken (printed).
TEST(Conductor, WhiteFurnaceKeepsItsEnergyWithMultipleScattering) {
    for (float r : {0.05f, 0.1f, 0.25f, 0.5f, 0.75f, 1.0f})
        for (double theta : {0.0, 40.0, 70.0, 85.0}) {
            const Vec3 wo = directionAt(theta);
            const float with = albedo(Conductor(r, kWhite, true, Color(0.0f)), wo, 200000);
            const float without = albedo(Conductor(r, kWhite, false, Color(0.0f)), wo, 200000);
            std::printf(
                "roughness %.2f, theta %2.0f: albedo %.4f with the lobe, %.4f without "
                "(table E %.4f)\n",
                r, theta, with, without, GgxAlbedo::get().albedo(wo.z, r));
            EXPECT_GE(with, 0.99f) << "roughness " << r << ", theta " << theta;
            EXPECT_LE(with, 1.01f) << "roughness " << r << ", theta " << theta;
            EXPECT_LE(without, with + 0.005f);
        }
}

TEST(Conductor, SmoothIsAFresnelWeightedMirror) {
    const Conductor m(0.0f, kCopper, true, Color(0.0f));
    ASSERT_TRUE(m.isSpecular());
    const Vec3 wo = directionAt(50.0);
    auto s = m.sample(wo, kNormal, 0.5f, Vec2(0.5f), TransportMode::Radiance);
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->specular);
    EXPECT_NEAR(s->wi.x, -wo.x, 1e-6f);
    EXPECT_NEAR(s->wi.z, wo.z, 1e-6f);
    const Color expected =
        fresnelConductor(wo.z, Color(0.21f, 1.12f, 1.24f), Color(4.14f, 2.59f, 2.38f));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(s->weight[c], expected[c], 1e-6f);
    EXPECT_EQ(m.f(wo, s->wi, kNormal), Color(0.0f));
}

TEST(ConductorFresnel, ComplexIorMatchesReferenceValuesAndSchlickItsF0) {
    // Normal incidence: ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2).
    const Color eta(0.21f, 1.12f, 1.24f), k(4.14f, 2.59f, 2.38f);
    const Color r0 = fresnelConductor(1.0f, eta, k);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(r0[c], (sqr(eta[c] - 1) + sqr(k[c])) / (sqr(eta[c] + 1) + sqr(k[c])), 1e-5f);
    // Grazing incidence reflects everything; k = 0 is a dielectric.
    EXPECT_NEAR(fresnelConductor(0.0f, eta, k).y, 1.0f, 1e-5f);
    EXPECT_NEAR(fresnelConductor(0.6f, Color(1.5f), Color(0.0f)).x, fresnelDielectric(0.6f, 1.5f),
                1e-5f);
    EXPECT_EQ(fresnelSchlickF0(1.0f, Color(0.3f)), Color(0.3f));
    EXPECT_NEAR(kWhite.average().x, 1.0f, 1e-6f);
    EXPECT_NEAR(ConductorFresnel::fromF0(Color(0.0f)).average().x, 1.0f / 21.0f, 1e-6f);
}

}  // namespace caustic
