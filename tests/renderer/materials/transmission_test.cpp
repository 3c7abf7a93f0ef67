// glTF's transmission (KHR_materials_transmission, KHR_materials_ior): the metallic-roughness
// surface mixed with a rough dielectric of weight (1 - metallic) transmission. Its sampling
// against its pdf (chi-square) in both transport modes' directions, reported values and
// densities, and energy: a white transmissive surface scatters at most what it receives.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/error.h"
#include "materials/metallic_roughness.h"
#include "materials/mixed_material.h"
#include "materials/rough_dielectric.h"
#include "renderer/materials/chi2.h"
#include "renderer/materials/scattered_energy.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

std::unique_ptr<Material> transmissive(const Color& base, float metallic, float roughness,
                                       float transmission, float ior = 1.5f) {
    auto surface =
        std::make_unique<MetallicRoughness>(base, metallic, roughness, true, Color(0.0f), ior);
    auto glass =
        std::make_unique<RoughDielectric>(roughness, ior, FresnelModel::Schlick, base, Color(0.0f));
    return std::make_unique<MixedMaterial>(std::move(surface), std::move(glass),
                                           (1.0f - metallic) * transmission);
}

TEST(Transmission, SamplingMatchesItsPdf) {
    const float transmissions[] = {0.5f, 1.0f};
    const float roughnesses[] = {0.2f, 0.6f};
    const double thetas[] = {0.0, 45.0, 80.0, 135.0};  // 135: from inside the surface
    const int tests = 2 * 2 * 4;
    const double significance = testing::chi2Significance(tests);
    for (float t : transmissions)
        for (float r : roughnesses)
            for (double theta : thetas) {
                auto m = transmissive(Color(0.9f, 0.6f, 0.3f), 0.2f, r, t);
                testing::expectSamplingMatchesPdf(*m, testing::directionAt(theta), significance,
                                                  "transmission " + std::to_string(t) +
                                                      ", roughness " + std::to_string(r) +
                                                      ", theta " + std::to_string(theta));
            }
}

TEST(Transmission, SamplesReportTheMixsValueAndDensity) {
    Rng rng(7);
    for (float t : {0.3f, 1.0f})
        testing::expectSamplesReportValueAndDensity(*transmissive(Color(0.8f), 0.0f, 0.4f, t), rng,
                                                    2000, 85.0);
}

// What the mix scatters is at most what arrives, and is its parts' energies weighted: the
// surface's and the rough dielectric's (which loses what would bounce between its microfacets
// more than once, most at roughness 1 and grazing angles).
TEST(Transmission, AWhiteTransmissiveSurfaceScattersAtMostWhatItReceives) {
    for (float roughness : {0.1f, 0.5f, 1.0f})
        for (float t : {0.5f, 1.0f})
            for (double theta : {0.0, 60.0, 85.0}) {
                const Vec3 wo = testing::directionAt(theta);
                auto energy = [&](const Material& m) {
                    return testing::scatteredEnergy(m, wo, 200000, TransportMode::Importance, 13)
                        .total.x;
                };
                const double mix = energy(*transmissive(Color(1.0f), 0.0f, roughness, t));
                const double surface =
                    energy(MetallicRoughness(Color(1.0f), 0.0f, roughness, true, Color(0.0f)));
                const double glass = energy(RoughDielectric(roughness, 1.5f, FresnelModel::Schlick,
                                                            Color(1.0f), Color(0.0f)));
                const double expected = (1.0 - t) * surface + t * glass;
                std::printf(
                    "roughness %.1f, transmission %.1f, theta %2.0f: scatters %.4f "
                    "(surface %.4f, glass %.4f, weighted %.4f)\n",
                    roughness, t, theta, mix, surface, glass, expected);
                // 200000 samples of weights near 1: a standard error below 0.002 on each.
                EXPECT_LE(mix, 1.0 + 0.006);
                EXPECT_NEAR(mix, expected, 0.01);
            }
}

TEST(Transmission, SceneFieldsAndTheirErrors) {
    using nlohmann::json;
    auto scene = [](const json& extra) {
        json m = {{"type", "metallic_roughness"}, {"metallic", 0}, {"roughness", 0.3}};
        m.update(extra);
        json doc = json::parse(R"({
          "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "width": 4, "height": 4},
          "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}],
          "environment": {"color": [1, 1, 1]}
        })");
        doc["materials"]["m"] = m;
        return testing::sceneFromJson(doc);
    };
    EXPECT_NO_THROW(scene({{"transmission", 1}, {"ior", 1.33}}));
    auto expectError = [&](const json& extra, const std::string& path, const std::string& what) {
        try {
            scene(extra);
            FAIL() << extra.dump();
        } catch (const InputError& e) {
            EXPECT_EQ(e.path(), path);
            EXPECT_NE(e.message().find(what), std::string::npos) << e.message();
        }
    };
    expectError({{"transmission", 2}}, "/materials/m/transmission", "must be in [0, 1]");
    expectError({{"ior", 0.5}}, "/materials/m/ior", "must be in [1, 10]");
    expectError({{"transmission", 0.5}, {"alpha_mode", "blend"}}, "/materials/m/transmission",
                "cannot be combined with textures or alpha yet");
}

}  // namespace
}  // namespace caustic
