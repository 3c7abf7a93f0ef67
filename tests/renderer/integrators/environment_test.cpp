// Scenes lit by an environment and by directional lights: known answers for every integrator, and
// naive, light-sampling and MIS path tracing agreeing per region under a sky with a small sun
// (statistics as in convergence_test.cpp).
#include <gtest/gtest.h>

#include "support/environment_maps.h"
#include "support/region_stats.h"
#include "support/temp_dir.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using nlohmann::json;
using testing::Region;
using testing::RegionStats;

constexpr double kFamilyWiseFalseAlarm = 1e-3;

RegionStats renderRegions(const Scene& scene, const json& settings,
                          const std::vector<Region>& regions) {
    RegionStats stats(scene.camera.width(), scene.camera.height(), regions);
    render(scene, testing::settingsFrom(settings), stats.callbacks());
    return stats;
}

// A diffuse sphere of albedo rho under a constant environment Le: it is convex, so no light it
// scatters comes back to it, and its radiance is rho Le everywhere, after any number of bounces.
TEST(EnvironmentKnownAnswer, ConvexDiffuseSphereReflectsAlbedoTimesLeInEveryIntegrator) {
    const json doc = json::parse(R"({
      "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 30, "width": 16, "height": 16},
      "materials": {"white": {"type": "diffuse", "albedo": [0.8, 0.5, 0.2]}},
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white"}],
      "environment": {"color": [0.5, 1, 2], "strength": 2}
    })");
    auto scene = testing::sceneFromJson(doc);
    const double Le[3] = {1.0, 2.0, 4.0}, rho[3] = {0.8, 0.5, 0.2};
    // The central 8 x 8 pixels see only the sphere; the corner 2 x 2 only the environment.
    const std::vector<Region> regions{{4, 4, 12, 12}, {0, 0, 2, 2}};
    const std::vector<std::string> variants = testing::integratorVariants();
    const double threshold =
        testing::twoSidedNormalQuantile(kFamilyWiseFalseAlarm / double(variants.size() * 3));
    for (const std::string& variant : variants) {
        json settings = testing::integratorVariant(variant);
        settings["spp"] = 256;
        settings["spp_per_pass"] = 4;
        settings["photons"] = 20000;
        RegionStats stats = renderRegions(*scene, settings, regions);
        for (int c = 0; c < 3; ++c) {
            const double expected = rho[c] * Le[c], se = stats.standardError(0, c);
            EXPECT_LE(std::abs(stats.mean(0, c) - expected), threshold * se + 1e-5)
                << variant << " channel " << c << ": " << stats.mean(0, c) << " +- " << se
                << ", expected " << expected;
            EXPECT_NEAR(stats.mean(1, c), Le[c], 1e-5) << variant << " background, channel " << c;
        }
    }
}

// A diffuse floor under a directional light of irradiance E at 60 degrees from the normal:
// radiance rho / pi E cos(60) everywhere on it, for every integrator (the floor is flat, so
// nothing it scatters returns to it).
TEST(DirectionalKnownAnswer, FloorRadianceIsAlbedoOverPiTimesIrradianceCosine) {
    const json doc = json::parse(R"({
      "camera": {"position": [0, 3, 0.01], "look_at": [0, 0, 0], "fov": 30, "width": 8, "height": 8},
      "materials": {"white": {"type": "diffuse", "albedo": [0.8, 0.5, 0.2]}},
      "shapes": [{"type": "quad", "origin": [-5, 0, -5], "u": [0, 0, 10], "v": [10, 0, 0],
                  "material": "white"}],
      "lights": [{"type": "directional", "direction": [0.8660254, -0.5, 0], "irradiance": [3, 2, 1]}]
    })");
    auto scene = testing::sceneFromJson(doc);
    const double E[3] = {3, 2, 1}, rho[3] = {0.8, 0.5, 0.2};
    const std::vector<Region> regions{{0, 0, 8, 8}};
    for (const std::string& variant : testing::integratorVariants()) {
        json settings = testing::integratorVariant(variant);
        settings["spp"] = 4;
        settings["photons"] = 20000;
        RegionStats stats = renderRegions(*scene, settings, regions);
        for (int c = 0; c < 3; ++c) {
            const double expected = rho[c] / kPi * E[c] * 0.5;
            // A delta light is found by light sampling alone, with no noise; the photon maps
            // hold no light here (a photon leaving the floor never returns).
            EXPECT_NEAR(stats.mean(0, c), expected, 1e-4 * expected) << variant << " " << c;
        }
    }
}

// A floor, a glass sphere and a rough metal sphere under a sky with a small, bright sun, with two
// emitters besides. The three path tracers find the lights differently: naive by BSDF sampling
// alone, light sampling by choosing a light by its contribution at the point (LocalLightSampler)
// and sampling it, MIS by both; with one max_depth they converge to one image.
TEST(EnvironmentConvergence, NaiveLightSamplingAndMisAgreePerRegion) {
    testing::TempDir dir;
    writeImage(dir.path() / "sky.exr", testing::skyWithSun(128, 64, 24, 18, 3, 400.0f));
    const json doc = json::parse(R"({
      "camera": {"position": [0, 1.2, 4], "look_at": [0, 0.4, 0], "fov": 40,
                 "width": 24, "height": 24},
      "materials": {
        "floor": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]},
        "glass": {"type": "dielectric", "ior": 1.5},
        "metal": {"type": "conductor", "roughness": 0.4, "f0": [0.9, 0.7, 0.4]},
        "lamp": {"type": "diffuse", "albedo": [0, 0, 0], "emission": [3, 2, 1]}
      },
      "shapes": [
        {"type": "quad", "origin": [-4, 0, -4], "u": [0, 0, 8], "v": [8, 0, 0], "material": "floor"},
        {"type": "sphere", "center": [-0.6, 0.5, 0], "radius": 0.5, "material": "glass"},
        {"type": "sphere", "center": [0.6, 0.5, 0], "radius": 0.5, "material": "metal"},
        {"type": "sphere", "center": [1.2, 1.3, 0.8], "radius": 0.15, "material": "lamp"},
        {"type": "quad", "origin": [-2, 0.01, 1], "u": [0.8, 0, 0], "v": [0, 0, -0.8],
         "material": "lamp"}
      ],
      "environment": {"file": "sky.exr", "rotation": 30}
    })");
    SceneOptions options;
    options.assetsDir = dir.path();
    auto scene = loadScene(doc, options);
    const int size = 24, passes = 96;
    const std::vector<Region> regions = testing::blockHierarchy(size, size, {4, 8, size});
    auto settings = [&](bool lightSampling, bool mis, uint64_t seed) {
        return json{{"integrator", "path"},
                    {"spp", passes * 16},
                    {"spp_per_pass", 16},
                    {"max_depth", 6},
                    {"light_sampling", lightSampling},
                    {"mis", mis},
                    {"seed", seed}};
    };
    RegionStats naive = renderRegions(*scene, settings(false, false, 1), regions);
    RegionStats light = renderRegions(*scene, settings(true, false, 2), regions);
    RegionStats mis = renderRegions(*scene, settings(true, true, 3), regions);
    const double threshold =
        testing::twoSidedNormalQuantile(kFamilyWiseFalseAlarm / double(regions.size() * 3 * 3));
    const testing::Comparison c1 = testing::compare(naive, light);
    const testing::Comparison c2 = testing::compare(naive, mis);
    const testing::Comparison c3 = testing::compare(light, mis);
    EXPECT_LE(c1.worstZ, threshold) << "naive vs light sampling: " << c1.describe(regions);
    EXPECT_LE(c2.worstZ, threshold) << "naive vs MIS: " << c2.describe(regions);
    EXPECT_LE(c3.worstZ, threshold) << "light sampling vs MIS: " << c3.describe(regions);
}

}  // namespace
}  // namespace caustic
