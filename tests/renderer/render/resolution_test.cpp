// The settings' width and height over the camera's: the size rendered, the field of view kept, and
// the limits held at the settings' paths.
#include <gtest/gtest.h>

#include "core/error.h"
#include "render/resolution.h"

namespace caustic {
namespace {

Scene sceneOf(int width, int height) {
    Scene scene;
    scene.camera =
        Camera(Vec3(0.0f), Vec3(0.0f, 0.0f, -1.0f), Vec3(0.0f, 1.0f, 0.0f), 40.0f, width, height);
    return scene;
}

struct Case {
    int askedWidth, askedHeight, width, height;
};

TEST(Resolution, SettingsOverTheCameraAndOneSideKeepsTheAspectRatio) {
    for (Case c : {Case{0, 0, 16, 12}, Case{32, 0, 32, 24}, Case{0, 6, 8, 6}, Case{20, 10, 20, 10},
                   Case{1, 0, 1, 1}}) {
        Scene scene = sceneOf(16, 12);
        RenderSettings settings;
        settings.width = c.askedWidth;
        settings.height = c.askedHeight;
        applyResolution(scene, settings, SceneOptions{});
        EXPECT_EQ(scene.camera.width(), c.width) << c.askedWidth << "x" << c.askedHeight;
        EXPECT_EQ(scene.camera.height(), c.height) << c.askedWidth << "x" << c.askedHeight;
        // The settings name the size rendered, for the job's settings and the --stats file.
        EXPECT_EQ(settings.width, c.width);
        EXPECT_EQ(settings.height, c.height);
    }
}

TEST(Resolution, AResizedCameraKeepsItsVerticalFieldOfView) {
    const Camera camera = sceneOf(16, 12).camera;
    const Camera wide = camera.resized(64, 12);
    // The top and bottom edges' rays and the centre's are the same; the sides widen with the
    // aspect ratio.
    for (float v : {0.0f, 0.5f, 1.0f}) {
        const Vec3 a = camera.generateRay(8.0f, 12.0f * v).d,
                   b = wide.generateRay(32.0f, 12.0f * v).d;
        EXPECT_NEAR(a.x, b.x, 1e-6f);
        EXPECT_NEAR(a.y, b.y, 1e-6f);
        EXPECT_NEAR(a.z, b.z, 1e-6f);
    }
    float x = 0, y = 0;
    ASSERT_TRUE(wide.raster(wide.generateRay(3.0f, 5.0f).d, x, y));
    EXPECT_NEAR(x, 3.0f, 1e-4f);
    EXPECT_NEAR(y, 5.0f, 1e-4f);
}

TEST(Resolution, LimitsAreHeldAtTheSettingsPaths) {
    SceneOptions limits;
    limits.maxResolution = 100;
    limits.maxPixels = 50 * 50;
    auto pathOf = [&](int width, int height) -> std::string {
        Scene scene = sceneOf(16, 12);
        RenderSettings settings;
        settings.width = width;
        settings.height = height;
        try {
            applyResolution(scene, settings, limits, "/settings");
        } catch (const InputError& e) {
            return e.path() + ": " + e.message();
        }
        return "";
    };
    EXPECT_EQ(pathOf(50, 101), "/settings/height: must be in [1, 100], got 101");
    // A side that follows the aspect ratio is held to the limits too, at the setting given.
    EXPECT_EQ(pathOf(0, 90),
              "/settings/height: makes a 120x90 image at the camera's aspect ratio: "
              "must be in [1, 100], got 120");
    EXPECT_EQ(pathOf(60, 0),
              "/settings/width: makes a 60x45 image at the camera's aspect ratio: "
              "width x height must be at most 2500 pixels");
    EXPECT_EQ(pathOf(50, 50), "");
}

}  // namespace
}  // namespace caustic
