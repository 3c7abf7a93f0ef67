// Acceptance of texture filtering (issue 38, item 4): a far, finely checkered plane at 4 spp is
// closer to its 4096-spp image with filtering by the pixel's footprint than with nearest-texel
// lookups, which alias.
#include <gtest/gtest.h>

#include "render/renderer.h"
#include "support/temp_dir.h"
#include "support/test_scenes.h"
#include "support/texture_images.h"

namespace caustic {
namespace {

using nlohmann::json;

std::vector<float> renderPlane(const testing::TempDir& dir, const std::string& filter, int spp) {
    json doc = json::parse(R"({
      "camera": {"position": [0, 1, 0], "look_at": [0, 0.8, -10], "fov": 40,
                 "width": 48, "height": 24},
      "materials": {"checks": {"type": "metallic_roughness", "metallic": 0, "roughness": 1,
                               "base_color_texture": {"file": "checker.png",
                                                      "transform": {"scale": [100, 100]}}}},
      "shapes": [{"type": "quad", "origin": [-100, 0, 0], "u": [200, 0, 0], "v": [0, 0, -200],
                  "material": "checks"}],
      "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": [3, 3, 3]}]
    })");
    doc["materials"]["checks"]["base_color_texture"]["filter"] = filter;
    auto scene = testing::loadWithAssets(dir, doc);
    RenderResult result = render(
        *scene, testing::settingsFrom({{"integrator", "raycast"}, {"spp", spp}, {"seed", 7}}));
    return result.film->meanRgb();
}

TEST(TextureFiltering, AFarCheckeredPlaneAt4SppIsCloserToItsReferenceFiltered) {
    testing::TempDir dir;
    // 8 x 8 squares a repeat, 2 repeats a unit: squares of 1/16 unit, some thousands of them in
    // a pixel at the horizon.
    testing::writeChecker(dir.path() / "checker.png", 64, 8);
    const std::vector<float> reference = renderPlane(dir, "nearest", 4096);
    const double nearest = testing::rmse(renderPlane(dir, "nearest", 4), reference);
    const double filtered = testing::rmse(renderPlane(dir, "anisotropic", 4), reference);
    const double trilinear = testing::rmse(renderPlane(dir, "trilinear", 4), reference);
    std::printf(
        "RMSE against 4096 spp (nearest texels): nearest %.5f, trilinear %.5f, "
        "anisotropic %.5f; nearest / anisotropic %.2f\n",
        nearest, trilinear, filtered, nearest / filtered);
    EXPECT_LT(filtered, nearest);
    EXPECT_LT(trilinear, nearest);
}

}  // namespace
}  // namespace caustic
