// The scene's lights and environment: what they load as, and every bad input an error at its path.
#include <gtest/gtest.h>

#include <fstream>
#include <limits>

#include "film/image_io.h"
#include "renderer/scene/base_scene.h"
#include "support/environment_maps.h"
#include "support/temp_dir.h"

namespace caustic {
namespace {

using testing::expectSceneError;
using testing::patched;

class LightLoader : public ::testing::Test {
protected:
    LightLoader() {
        options_.assetsDir = dir_.path();
        writeImage(dir_.path() / "sky.exr", testing::skyWithSun(16, 8, 3, 2));
    }
    void expectError(const Json& doc, const std::string& path, const std::string& message) {
        expectSceneError(doc, path, message, options_);
    }
    testing::TempDir dir_;
    SceneOptions options_;
};

TEST_F(LightLoader, LoadsEveryLightKindAndTheEnvironment) {
    Json doc = patched("/lights", Json::parse(R"([
        {"type": "point", "position": [0, 2, 0], "intensity": [1, 2, 3]},
        {"type": "point", "position": [0, 2, 0], "candela": 683, "color": [1, 0.5, 0.25]},
        {"type": "spot", "position": [0, 2, 0], "direction": [0, -1, 0], "intensity": [1, 1, 1],
         "inner_angle": 10, "outer_angle": 20},
        {"type": "directional", "direction": [0, -1, 0], "lux": 683}
    ])"));
    doc["environment"] = {{"file", "sky.exr"}, {"strength", 2}, {"rotation", 45}};
    auto scene = loadScene(doc, options_);
    ASSERT_EQ(scene->lights.size(), 5u);
    ASSERT_NE(scene->environment, nullptr);
    EXPECT_EQ(scene->lights[scene->environmentIndex].get(), scene->environment);
    EXPECT_EQ(scene->directLights.pmf(Vec3(0.0f), scene->environmentIndex), 0.5f);
    EXPECT_GT(scene->environmentBytes, 16u * 8u * 12u);
    // 683 candela of colour (1, 0.5, 0.25) is that many W/sr: 4 pi of power in red.
    EXPECT_NEAR(scene->lights[1]->power().g, 0.5f * 4.0f * kPi, 1e-4f);

    // For admission: the size from the header, the same bytes counted.
    SceneOptions counting = options_;
    counting.countMeshesOnly = true;
    auto counted = loadScene(doc, counting);
    EXPECT_EQ(counted->environmentBytes, EnvironmentLight::bytesFor(16, 8));
    EXPECT_LE(counted->environmentBytes, scene->environmentBytes + 16 * 8 * 8);
}

TEST_F(LightLoader, BadLightsAreErrorsAtTheirPath) {
    auto light = [](const char* text) {
        return patched("/lights", Json::array({Json::parse(text)}));
    };
    expectError(light(R"({"type": "area"})"), "/lights/0/type",
                "unknown value \"area\"; valid: directional, point, spot");
    expectError(light(R"({"type": "spot", "position": [0, 1, 0], "direction": [0, 0, 0],
                          "intensity": [1, 1, 1]})"),
                "/lights/0/direction", "must not be zero");
    expectError(light(R"({"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0],
                          "intensity": [1, 1, 1], "inner_angle": 30, "outer_angle": 20})"),
                "/lights/0/inner_angle", "must be <= outer_angle");
    expectError(light(R"({"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0],
                          "intensity": [1, 1, 1], "outer_angle": 95})"),
                "/lights/0/outer_angle", "must be in [0, 90] degrees");
    expectError(light(R"({"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0],
                          "intensity": [1, 1, 1], "outer_angle": 0})"),
                "/lights/0/outer_angle", "must be > 0");
    expectError(light(R"({"type": "point", "position": [0, 1, 0], "intensity": [1, 1, 1],
                          "candela": 5})"),
                "/lights/0/intensity", "give either intensity or color and candela, not both");
    expectError(light(R"({"type": "point", "position": [0, 1, 0], "candela": -5})"),
                "/lights/0/candela", "must be >= 0");
    expectError(light(R"({"type": "directional", "direction": [0, -1, 0]})"),
                "/lights/0/irradiance", "missing required field");
    expectError(light(R"({"type": "directional", "direction": [0, -1, 0], "lux": 1,
                          "irradiance": [1, 1, 1]})"),
                "/lights/0/irradiance", "give either irradiance or color and lux, not both");
    expectError(light(R"({"type": "directional", "direction": [0, -1, 0], "irradiance": [1, 1, 1],
                          "position": [0, 0, 0]})"),
                "/lights/0/position",
                "unknown field; valid fields here: direction, irradiance, lux, type");
}

TEST_F(LightLoader, BadEnvironmentsAreErrorsAtTheirPath) {
    auto env = [](const Json& e) { return patched("/environment", e); };
    const std::string needs =
        "an environment needs \"color\" or \"file\" (an EXR or HDR image in the assets folder), "
        "not both";
    expectError(env(Json::object()), "/environment", needs);
    expectError(env({{"color", {1, 1, 1}}, {"file", "sky.exr"}}), "/environment", needs);
    expectError(env({{"color", {1, 1, 1}}, {"strength", -1}}), "/environment/strength",
                "must be >= 0");
    expectError(env({{"color", {1, 1, 1}}, {"rotation", 10}}), "/environment/rotation",
                "applies to a file only");
    expectError(env({{"file", "sky.png"}}), "/environment/file",
                "must be an EXR or HDR (Radiance) image, got \"sky.png\"");
    expectError(env({{"file", "missing.exr"}}), "/environment/file",
                "no file \"missing.exr\" in the assets folder");
    expectError(env({{"file", "../sky.exr"}}), "/environment/file",
                "\"../sky.exr\" must not leave the assets folder (\"..\")");
    Json both = env({{"color", {1, 1, 1}}});
    both["background"] = {1, 1, 1};
    expectError(both, "/background", "give either background or environment, not both");

    // An image that is not one, one over the pixel limit, one with a texel that is not finite.
    std::ofstream(dir_.path() / "text.exr") << "not an image";
    try {
        loadScene(env({{"file", "text.exr"}}), options_);
        ADD_FAILURE() << "loaded a text file as an image";
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), "/environment/file");
        EXPECT_NE(e.message().find("cannot read text.exr"), std::string::npos) << e.message();
    }
    SceneOptions small = options_;
    small.maxPixels = 100;
    Json tiny = env({{"file", "sky.exr"}});
    tiny["camera"]["width"] = tiny["camera"]["height"] = 8;
    expectSceneError(tiny, "/environment/file", "sky.exr is 16 x 8 pixels, over the limit of 100",
                     small);
    RgbImage bad = testing::skyWithSun(4, 2, 1, 1);
    bad.pixels[3 * 5 + 1] = std::numeric_limits<float>::quiet_NaN();
    writeImage(dir_.path() / "nan.exr", bad);
    expectError(env({{"file", "nan.exr"}}), "/environment/file",
                "texel (1, 1) is negative or not finite");
}

}  // namespace
}  // namespace caustic
