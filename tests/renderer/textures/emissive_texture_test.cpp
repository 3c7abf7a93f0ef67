// An emissive texture makes an area light whose radiance follows the image: an emitter whose
// texture is black on one half lights a floor as the other half alone, emitting uniformly, does
// (path tracing with light sampling and MIS, and photon mapping), and the camera sees the image.
#include <gtest/gtest.h>

#include "render/renderer.h"
#include "support/region_stats.h"
#include "support/temp_dir.h"
#include "support/test_scenes.h"
#include "support/texture_images.h"

namespace caustic {
namespace {

using nlohmann::json;
using testing::Region;
using testing::RegionStats;

// A 2 x 2 emitter facing down at height 2 over a diffuse floor; `emitter` is its shape.
json lampOverFloor(const json& emitter, const json& lampMaterial) {
    json doc = json::parse(R"({
      "camera": {"position": [0, 1.2, 3], "look_at": [0, 0, 0], "fov": 40, "width": 24, "height": 24},
      "materials": {"floor": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]}},
      "shapes": [{"type": "quad", "origin": [-4, 0, 4], "u": [8, 0, 0], "v": [0, 0, -8],
                  "material": "floor"}]
    })");
    doc["materials"]["lamp"] = lampMaterial;
    doc["shapes"].push_back(emitter);
    return doc;
}

TEST(EmissiveTexture, AHalfBlackTextureLightsAsTheOtherHalfAlone) {
    testing::TempDir dir;
    // Black where s < 0.5, white where s >= 0.5 (sRGB 1 is linear 1).
    testing::writeTextureImage(dir.path() / "half.png", 8, 8, 3,
                               [](int x, int, int) { return x < 4 ? 0.0f : 1.0f; });
    const json textured = lampOverFloor(
        json::parse(R"({"type": "quad", "origin": [-1, 2, -1], "u": [2, 0, 0], "v": [0, 0, 2],
                        "material": "lamp"})"),
        {{"type", "metallic_roughness"},
         {"base_color", {0, 0, 0}},
         {"emission", {3, 3, 3}},
         {"emissive_texture", "half.png"}});
    const json half = lampOverFloor(
        json::parse(R"({"type": "quad", "origin": [0, 2, -1], "u": [1, 0, 0], "v": [0, 0, 2],
                        "material": "lamp"})"),
        {{"type", "diffuse"}, {"albedo", {0, 0, 0}}, {"emission", {3, 3, 3}}});
    auto a = testing::loadWithAssets(dir, textured), b = testing::loadWithAssets(dir, half);
    // The floor in the image's lower half: its left and right parts.
    const std::vector<Region> regions{{2, 14, 12, 24}, {12, 14, 22, 24}};
    const std::vector<json> variants{
        {{"integrator", "path"}, {"spp", 256}, {"spp_per_pass", 8}},
        {{"integrator", "photon"}, {"spp", 64}, {"spp_per_pass", 2}, {"photons", 40000}}};
    const double threshold = testing::twoSidedNormalQuantile(1e-3 / double(2 * 2 * 3));
    for (const json& settings : variants) {
        RegionStats sa(24, 24, regions), sb(24, 24, regions);
        render(*a, testing::settingsFrom(settings), sa.callbacks());
        render(*b, testing::settingsFrom(settings), sb.callbacks());
        for (size_t r = 0; r < regions.size(); ++r)
            for (int c = 0; c < 3; ++c) {
                const double se = std::hypot(sa.standardError(r, c), sb.standardError(r, c));
                EXPECT_LE(std::abs(sa.mean(r, c) - sb.mean(r, c)), threshold * se)
                    << settings.dump() << " region " << r << ": " << sa.mean(r, c) << " vs "
                    << sb.mean(r, c) << " +- " << se;
                EXPECT_GT(sa.mean(r, c), 0.0);
            }
    }
    // Seen from below, the lamp shows its texture: dark on the left, 3 on the right.
    json look = textured;
    look["camera"] = json::parse(R"({"position": [0, 0.5, 0], "look_at": [0, 2, 0], "up": [0, 0, 1],
                                     "fov": 40, "width": 16, "height": 16})");
    const std::vector<float> rgb =
        render(*testing::loadWithAssets(dir, look),
               testing::settingsFrom({{"integrator", "raycast"}, {"spp", 4}}))
            .film->meanRgb();
    EXPECT_LT(rgb[3 * (8 * 16 + 3)], 0.05f);
    EXPECT_NEAR(rgb[3 * (8 * 16 + 12)], 3.0f, 0.05f);
}

// An emissive texture the camera sees is filtered over the share of the pixel each camera ray
// covers, whether the integrator's own rays see it (emission_samples 0) or the render's
// seen-emission rays do (spp x emission_samples of them): the two images agree to their noise,
// where a whole pixel's footprint on the second would blur every edge of the checker.
TEST(EmissiveTexture, SeenDirectlyItIsFilteredOverItsRaysShareOfThePixel) {
    testing::TempDir dir;
    testing::writeChecker(dir.path() / "checker.png", 32, 16);  // cells of 2 texels
    json doc = json::parse(R"({
      "camera": {"position": [0, 0, 1], "look_at": [0, 0, 0], "fov": 90, "width": 32, "height": 32},
      "materials": {"lamp": {"type": "metallic_roughness", "base_color": [0, 0, 0],
                             "emission": [1, 1, 1], "emissive_texture": "checker.png"}},
      "shapes": [{"type": "quad", "origin": [-1, -1, 0], "u": [2, 0, 0], "v": [0, 2, 0],
                  "material": "lamp"}]
    })");
    auto scene = testing::loadWithAssets(dir, doc);
    auto image = [&](int emissionSamples) {
        return render(*scene, testing::settingsFrom({{"integrator", "path"},
                                                     {"spp", 64},
                                                     {"emission_samples", emissionSamples}}))
            .film->meanRgb();
    };
    const double difference = testing::rmse(image(0), image(4));
    std::printf("RMSE between the integrator's and the seen-emission rays' images: %.4f\n",
                difference);
    // Their noise alone: 0.025 (the camera rays' sampling of the checker's edges); with a whole
    // pixel's footprint on the seen-emission rays, 0.070.
    EXPECT_LT(difference, 0.04);
}

}  // namespace
}  // namespace caustic
