// glTF's metallic-roughness material: its sampling against its pdf (chi-square) over a grid of
// metallic, roughness, base colour and angle; sampled values and densities; reciprocity; the
// specification's formula at a known pair; a white metal in a white furnace with the multiple-
// scattering lobe (and the loss without it, printed); energy conservation of the dielectric.
#include "materials/metallic_roughness.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "core/rng.h"
#include "core/sampling.h"
#include "materials/ggx.h"
#include "materials/ggx_albedo.h"
#include "renderer/materials/chi2.h"
#include "renderer/materials/scattered_energy.h"

namespace caustic {
namespace {

using testing::directionAt;
const Vec3 kNormal(0.0f, 0.0f, 1.0f);
const Color kOrange(0.9f, 0.45f, 0.1f);

Color albedo(const Material& m, const Vec3& wo, int n) {
    return Color(testing::scatteredEnergy(m, wo, n, TransportMode::Radiance, 11).total);
}

}  // namespace

TEST(MetallicRoughness, SamplingMatchesItsPdf) {
    const float metallics[] = {0.0f, 0.5f, 1.0f};
    const float roughnesses[] = {0.1f, 0.4f, 1.0f};
    const double thetas[] = {0.0, 45.0, 80.0};
    const int tests = 3 * 3 * 3 * 2;
    const double significance = testing::chi2Significance(tests);
    for (float metallic : metallics)
        for (float r : roughnesses)
            for (double theta : thetas)
                for (const Color& base : {kOrange, Color(1.0f)}) {
                    const MetallicRoughness m(base, metallic, r, true, Color(0.0f));
                    testing::expectSamplingMatchesPdf(
                        m, directionAt(theta), significance,
                        "metallic " + std::to_string(metallic) + ", roughness " +
                            std::to_string(r) + ", theta " + std::to_string(theta) +
                            (base == kOrange ? ", orange" : ", white"));
                }
}

TEST(MetallicRoughness, SamplesReportTheirValueAndDensity) {
    Rng rng(3);
    for (float metallic : {0.0f, 0.3f, 1.0f})
        testing::expectSamplesReportValueAndDensity(
            MetallicRoughness(kOrange, metallic, 0.5f, true, Color(0.0f)), rng, 2000, 89.0);
}

TEST(MetallicRoughness, IsReciprocalAndReflectsFromBothSides) {
    Rng rng(5);
    testing::expectReciprocalTwoSidedReflector(
        MetallicRoughness(kOrange, 0.4f, 0.35f, true, Color(0.0f)), rng, 1000);
}

// The specification's formula (glTF 2.0, Appendix B.3.5) at one pair of directions, but for the
// dielectric's diffuse weight: what the specular layer leaves in each direction (Kulla and Conty's
// reciprocal form) instead of 1 - F(v.h).
TEST(MetallicRoughness, IsTheGltfFormulaWithAnEnergyConservingDiffuse) {
    const float metallic = 0.3f, roughness = 0.6f;
    const MetallicRoughness m(kOrange, metallic, roughness, /*multipleScattering=*/false,
                              Color(0.0f));
    const Vec3 v = directionAt(35.0, 0.2), l = directionAt(60.0, 2.5);
    const Vec3 h = glm::normalize(v + l);
    const Ggx ggx(roughness * roughness, roughness * roughness);
    const float vh = glm::dot(v, h);
    const float spec = ggx.D(h) * ggx.G(v, l) / (4.0f * v.z * l.z);
    const float fd = 0.04f + 0.96f * std::pow(1.0f - vh, 5.0f);
    const Color fm = kOrange + (Color(1.0f) - kOrange) * std::pow(1.0f - vh, 5.0f);
    const GgxAlbedo& table = GgxAlbedo::get();
    auto layer = [&](float mu) {
        return 0.04f * table.albedo(mu, roughness) + 0.96f * table.schlickAlbedo(mu, roughness);
    };
    const float average =
        0.04f * table.average(roughness) + 0.96f * table.schlickAverage(roughness);
    const Color diffuse =
        kOrange * ((1.0f - layer(v.z)) * (1.0f - layer(l.z)) / (kPi * (1.0f - average)));
    const Color expected = (1.0f - metallic) * (fd * spec + diffuse) + metallic * fm * spec;
    const Color f = m.f(v, l, kNormal);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], expected[c], 1e-5f * expected[c]);
}

// Metallic 1, base colour white: F = 1, a white rough metal. With the lobe it reflects all it
// receives; without it, what single scattering loses (printed).
TEST(MetallicRoughness, WhiteMetalInAWhiteFurnaceKeepsItsEnergy) {
    for (float r : {0.05f, 0.1f, 0.25f, 0.5f, 0.75f, 1.0f})
        for (double theta : {0.0, 40.0, 70.0, 85.0}) {
            const Vec3 wo = directionAt(theta);
            const float with =
                albedo(MetallicRoughness(Color(1.0f), 1.0f, r, true, Color(0.0f)), wo, 200000).x;
            const float without =
                albedo(MetallicRoughness(Color(1.0f), 1.0f, r, false, Color(0.0f)), wo, 200000).x;
            std::printf(
                "metallic-roughness, white metal, roughness %.2f, theta %2.0f: albedo "
                "%.4f with the lobe, %.4f without\n",
                r, theta, with, without);
            EXPECT_GE(with, 0.99f) << "roughness " << r << ", theta " << theta;
            EXPECT_LE(with, 1.01f) << "roughness " << r << ", theta " << theta;
        }
}

// A white dielectric (metallic 0, base 1) reflects what it receives, less the small loss of the
// specular layer's single scattering: its albedo is E_d(mu_o) + (1 - E_d(mu_o)) = 1 exactly for the
// tabulated E_d. The specification's own weight, 1 - F(v.h), would create light at grazing angles
// (printed: its albedo, E_d(mu_o) + the mean over cosine-distributed wi of 1 - F(v.h)).
TEST(MetallicRoughness, DielectricNeverCreatesEnergy) {
    Rng rng(9);
    for (float r : {0.05f, 0.3f, 1.0f})
        for (double theta : {0.0, 60.0, 85.0}) {
            const Vec3 wo = directionAt(theta);
            const float a =
                albedo(MetallicRoughness(Color(1.0f), 0.0f, r, true, Color(0.0f)), wo, 200000).x;
            double literalDiffuse = 0.0;
            const int n = 100000;
            for (int i = 0; i < n; ++i) {
                const Vec3 wi = sampleCosineHemisphere(rng.uniform2());
                const float vh = glm::dot(wo, glm::normalize(wo + wi));
                literalDiffuse += (1.0 - (0.04 + 0.96 * std::pow(1.0 - vh, 5.0))) / n;
            }
            const GgxAlbedo& table = GgxAlbedo::get();
            const double layer =
                0.04 * table.albedo(float(wo.z), r) + 0.96 * table.schlickAlbedo(float(wo.z), r);
            std::printf(
                "metallic-roughness, white dielectric, roughness %.2f, theta %2.0f: albedo "
                "%.4f; with the specification's diffuse weight %.4f\n",
                r, theta, a, layer + literalDiffuse);
            EXPECT_LE(a, 1.005f) << "roughness " << r << ", theta " << theta;
            EXPECT_GE(a, 0.99f) << "roughness " << r << ", theta " << theta;
        }
}

}  // namespace caustic
