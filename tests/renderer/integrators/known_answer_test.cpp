// Known-answer tests for the integrators that exist: images compared with analytic radiance, or
// with themselves under a change that must not alter them.
#include <gtest/gtest.h>

#include <cstring>

#include "integrators/integrator.h"
#include "support/point_light_plane.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using nlohmann::json;
using testing::emissiveWallScene;
using testing::exampleScene;
using testing::mergePatched;
using testing::pointLightOverPlane;
using testing::sceneFromJson;
using testing::settingsFrom;

class PointLightPlane : public ::testing::TestWithParam<std::string> {};

TEST_P(PointLightPlane, EveryPixelMatchesTheAnalyticRadiance) {
    auto scene = sceneFromJson(pointLightOverPlane(48, 32));
    RenderResult r = render(*scene, settingsFrom({{"integrator", GetParam()}, {"spp", 64}}));
    const Film& film = *r.film;
    ASSERT_EQ(film.passes(), 64);
    double worst = 0;
    EXPECT_EQ(testing::pixelsOffTheAnalyticValue(film, scene->camera, worst), 0)
        << "largest error / tolerance: " << worst;
    EXPECT_EQ(r.stats.droppedSamples, 0u);
}

INSTANTIATE_TEST_SUITE_P(Integrators, PointLightPlane, ::testing::Values("raycast", "whitted"));

TEST(Dielectric, SphereOfIorOneLeavesTheImageUnchanged) {
    // Each sample's own ray sees the wall, through the sphere or not (as in GlassOfIorOne).
    RenderSettings settings =
        settingsFrom({{"integrator", "whitted"}, {"spp", 4}, {"emission_samples", 0}});
    auto plain = sceneFromJson(emissiveWallScene(false, 40));
    auto withSphere = sceneFromJson(emissiveWallScene(true, 40));
    std::vector<float> a = render(*plain, settings).film->meanRgb();
    RenderResult r = render(*withSphere, settings);
    std::vector<float> b = r.film->meanRgb();
    ASSERT_EQ(a.size(), b.size());
    // Each sample's ray crosses the sphere twice with R = 0 and T = 1; only the rounding of the two
    // refracted directions differs, and the wall's radiance is uniform.
    for (size_t i = 0; i < a.size(); ++i) ASSERT_NEAR(b[i], a[i], 1e-6f * a[i]) << "at value " << i;
    // And the sphere was really traced: twice the rays of the plain scene where it is seen.
    EXPECT_GT(r.stats.rays, render(*plain, settings).stats.rays);
}

TEST(Determinism, SameImageWithOneAndTwoThreads) {
    auto scene = sceneFromJson(testing::exampleScene("cornell-spheres", 64, 48));
    for (const std::string& integrator : testing::integratorVariants()) {
        for (const std::string sampler : {"independent", "sobol", "sobol_sequence", "adaptive"}) {
            SCOPED_TRACE(sampler);
            // Few photons: photon tracing runs in parallel too, and must not depend on it either.
            // Adaptive sampling: 2 passes after its pilot of 8.
            const bool adaptive = sampler == "adaptive";
            json base = mergePatched(testing::integratorVariant(integrator),
                                     {{"spp", adaptive ? 40 : 8},
                                      {"spp_per_pass", 4},
                                      {"seed", 17},
                                      {"photons", 20000},
                                      {"sampler", adaptive ? "sobol" : sampler},
                                      {"adaptive", adaptive}});
            RenderResult one = render(*scene, settingsFrom(mergePatched(base, {{"threads", 1}})));
            RenderResult two = render(*scene, settingsFrom(mergePatched(base, {{"threads", 2}})));
            std::vector<float> a = one.film->meanRgb(), b = two.film->meanRgb();
            ASSERT_EQ(a.size(), b.size());
            EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0) << integrator;
            EXPECT_EQ(one.stats.rays, two.stats.rays) << integrator;
            // A different seed gives a different image (the seed is really used).
            RenderResult other = render(*scene, settingsFrom(mergePatched(base, {{"seed", 18}})));
            std::vector<float> c = other.film->meanRgb();
            EXPECT_NE(std::memcmp(a.data(), c.data(), a.size() * sizeof(float)), 0) << integrator;
        }
    }
}

TEST(PhotonCaustics, DirectLightOnlyIsThePathTracedImageBitForBit) {
    // With max_depth 1 no caustic fits in a path (a photon needs a bounce before the lookup's
    // vertex), and the camera paths draw the same random numbers: the same image, bit for bit.
    auto scene = sceneFromJson(exampleScene("cornell-spheres", 24, 16));
    const json base{{"max_depth", 1}, {"spp", 8}, {"spp_per_pass", 4}, {"photons", 2000}};
    std::vector<float> a = render(*scene, settingsFrom(base)).film->meanRgb();
    RenderResult mapped =
        render(*scene, settingsFrom(mergePatched(base, {{"caustics", "photon_map"}})));
    std::vector<float> b = mapped.film->meanRgb();
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
    // The photons were traced all the same (the map would have been read with max_depth 2).
    EXPECT_GT(mapped.stats.rays, render(*scene, settingsFrom(base)).stats.rays);
}

TEST(PhotonCaustics, AreNotTracedInASceneWithoutSpecularSurfaces) {
    // cornell-box is diffuse only: no caustic exists, the map stays empty and costs no ray, and
    // the image is the path-traced one bit for bit.
    auto scene = sceneFromJson(exampleScene("cornell-box", 24, 16));
    const json base{{"spp", 8}, {"spp_per_pass", 4}, {"photons", 2000}};
    RenderResult plain = render(*scene, settingsFrom(base));
    RenderResult mapped =
        render(*scene, settingsFrom(mergePatched(base, {{"caustics", "photon_map"}})));
    std::vector<float> a = plain.film->meanRgb(), b = mapped.film->meanRgb();
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
    EXPECT_EQ(mapped.stats.rays, plain.stats.rays);
}

}  // namespace
}  // namespace caustic
