// A rough white metal (F0 = 1) in a white furnace under the path tracer: a sphere with nothing
// else, under a background of radiance 1. A path meets the convex sphere at most once, so each
// pixel's expectation is the directional albedo of the metal at the angle the camera sees it: 1
// with the multiple-scattering lobe (up to the albedo table's interpolation, under 0.5%: the
// material's furnace test measures it), less without it. The path tracer's sampling, weights and
// frames are checked with the material.
#include <gtest/gtest.h>

#include "core/student_t.h"
#include "furnace_support.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using nlohmann::json;

json metalFurnace(double roughness, bool multipleScattering) {
    return {{"camera",
             {{"position", {0.3, 0.4, 3.0}},
              {"look_at", {0, 0, 0}},
              {"fov", 45},
              {"width", 12},
              {"height", 12}}},
            {"materials",
             {{"metal",
               {{"type", "conductor"},
                {"roughness", roughness},
                {"f0", {1, 1, 1}},
                {"multiple_scattering", multipleScattering}}}}},
            {"shapes",
             {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}, {"material", "metal"}}}},
            {"background", {1, 1, 1}}};
}

RenderResult renderFurnace(double roughness, bool multipleScattering) {
    return render(*testing::sceneFromJson(metalFurnace(roughness, multipleScattering)),
                  testing::settingsFrom({{"integrator", "path"},
                                         {"spp", 256},
                                         {"spp_per_pass", 4},
                                         {"seed", 9},
                                         {"emission_samples", 0}}));
}

// False alarms 1e-3 over every pixel value and image mean of the two roughnesses, Student t with
// 63 degrees of freedom (64 passes).
const double kThreshold = testing::studentThreshold(1e-3 / (2.0 * 3 * (12 * 12 + 1)), 63);

}  // namespace

TEST(ConductorFurnace, WhiteRoughMetalStaysWhiteUnderPathTracing) {
    for (double roughness : {0.5, 1.0}) {
        SCOPED_TRACE(roughness);
        RenderResult r = renderFurnace(roughness, true);
        EXPECT_EQ(r.stats.droppedSamples, 0u);
        // 0.005: the albedo table's interpolation error, a bias the pass variance cannot see.
        testing::expectUniform(*r.film, {1, 1, 1}, kThreshold, 0.005);
    }
}

TEST(ConductorFurnace, WithoutTheLobeRoughMetalDarkens) {
    // At roughness 1 single scattering keeps 31% to 78% of the light by angle (the material's
    // furnace test prints it): the image mean falls well below 1.
    RenderResult r = renderFurnace(1.0, false);
    testing::UniformCheck c = testing::checkUniform(*r.film, {1, 1, 1}, kThreshold, 0.005);
    EXPECT_LT(c.imageMean[0], 0.8);
    EXPECT_GT(c.imageMean[0], 0.3);
}

}  // namespace caustic
