// Good scenes: the examples load as expected, and defaults apply.
// Scene loading: every kind of bad scene is an InputError with the exact JSON path and message;
// the example scenes load with the expected primitives, lights, materials and defaults.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "lights/area_light.h"
#include "lights/point_light.h"
#include "materials/dielectric.h"
#include "materials/diffuse.h"
#include "renderer/scene/base_scene.h"
#include "scene/json_reader.h"
#include "scene/scene.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using testing::baseScene;
using testing::patched;
using testing::repoSceneOptions;

// --- good scenes ---

size_t countKind(const Geometry& g, PrimKind kind) {
    size_t n = 0;
    for (uint32_t p = 0; p < g.size(); ++p) n += g.kind(p) == kind;
    return n;
}

size_t countAreaLights(const Scene& scene) {
    size_t n = 0;
    for (const auto& light : scene.lights)
        n += dynamic_cast<const AreaLight*>(light.get()) != nullptr;
    return n;
}

std::vector<std::string> sorted(std::vector<std::string> v) {
    std::sort(v.begin(), v.end());
    return v;
}

TEST(SceneLoaderExamples, CornellSpheres) {
    auto scene = loadScene(testing::exampleScene("cornell-spheres"), repoSceneOptions());
    EXPECT_EQ(countKind(scene->geometry, PrimKind::Quad), 6u);
    EXPECT_EQ(countKind(scene->geometry, PrimKind::Sphere), 2u);
    EXPECT_EQ(countKind(scene->geometry, PrimKind::Triangle), 0u);
    ASSERT_EQ(scene->lights.size(), 1u);
    EXPECT_EQ(countAreaLights(*scene), 1u);
    EXPECT_EQ(sorted(scene->materialNames),
              (std::vector<std::string>{"glass", "green", "lamp", "mirror", "red", "white"}));
    EXPECT_EQ(scene->materials.size(), scene->materialNames.size());
    EXPECT_EQ(scene->camera.width(), 512);
    EXPECT_EQ(scene->camera.height(), 512);
    EXPECT_EQ(scene->settings, (Json{{"spp", 64}}));
    EXPECT_EQ(scene->background, Color(0.0f));
    // The glass sphere is the last primitive: a dielectric of IOR 1.5.
    const auto* glass =
        dynamic_cast<const Dielectric*>(&scene->material(scene->geometry.size() - 1));
    ASSERT_NE(glass, nullptr);
    EXPECT_FLOAT_EQ(glass->ior(), 1.5f);
}

TEST(SceneLoaderExamples, CornellBox) {
    auto scene = loadScene(testing::exampleScene("cornell-box"), repoSceneOptions());
    EXPECT_EQ(scene->geometry.size(), 18u);
    EXPECT_EQ(countKind(scene->geometry, PrimKind::Quad), 18u);
    ASSERT_EQ(scene->lights.size(), 1u);
    EXPECT_EQ(countAreaLights(*scene), 1u);
    EXPECT_EQ(sorted(scene->materialNames),
              (std::vector<std::string>{"green", "lamp", "red", "white"}));
}

TEST(SceneLoaderExamples, Bunny) {
    auto scene = loadScene(testing::exampleScene("bunny"), repoSceneOptions());
    EXPECT_EQ(countKind(scene->geometry, PrimKind::Triangle), 69451u);
    EXPECT_EQ(countKind(scene->geometry, PrimKind::Quad), 6u);
    EXPECT_EQ(scene->geometry.size(), 69451u + 6u);
    ASSERT_EQ(scene->lights.size(), 1u);
    EXPECT_EQ(countAreaLights(*scene), 1u);
    EXPECT_EQ(sorted(scene->materialNames),
              (std::vector<std::string>{"green", "lamp", "red", "white"}));
    // The bunny (scale 8, translated to y = -1.265) stands on the floor of the box.
    Bounds3 b;
    for (uint32_t p = 0; p < scene->geometry.size(); ++p)
        if (scene->geometry.kind(p) == PrimKind::Triangle) b.extend(scene->geometry.bounds(p));
    EXPECT_NEAR(b.lo.y, -1.0f, 0.05f);
    EXPECT_LT(b.hi.y, 0.5f);
}

// The study's scenes (docs/study/): a glass sphere under a small sphere light, three meshes, and
// a room lit by a lamp that faces the ceiling.
TEST(SceneLoaderExamples, StudyScenes) {
    auto glass = loadScene(testing::exampleScene("caustic-glass"), repoSceneOptions());
    EXPECT_EQ(countKind(glass->geometry, PrimKind::Sphere), 2u);
    EXPECT_EQ(countAreaLights(*glass), 1u);
    auto meshes = loadScene(testing::exampleScene("meshes"), repoSceneOptions());
    // The bunny's 69451 triangles, the teapot's and spot's.
    EXPECT_GT(countKind(meshes->geometry, PrimKind::Triangle), 69451u + 5000u);
    EXPECT_EQ(countAreaLights(*meshes), 1u);
    auto indirect = loadScene(testing::exampleScene("indirect"), repoSceneOptions());
    EXPECT_EQ(countAreaLights(*indirect), 1u);
    EXPECT_EQ(countKind(indirect->geometry, PrimKind::Quad), 6u);
}

TEST(SceneLoaderDefaults, CameraDefaults) {
    auto scene = loadScene(baseScene(), repoSceneOptions());
    EXPECT_EQ(scene->camera.width(), 512);
    EXPECT_EQ(scene->camera.height(), 512);
    // Default up is +y: the image's top-centre ray points up and forward.
    Ray top = scene->camera.generateRay(256.0f, 0.0f);
    EXPECT_GT(top.d.y, 0.0f);
    EXPECT_NEAR(top.d.x, 0.0f, 1e-6f);
    // Default fov is 40 degrees: the top-centre ray is 20 degrees above the axis.
    float degrees = std::atan2(top.d.y, -top.d.z) * 180.0f / kPi;
    EXPECT_NEAR(degrees, 20.0f, 1e-3f);
    EXPECT_EQ(scene->background, Color(0.0f));
    EXPECT_TRUE(scene->settings.is_object());
    EXPECT_TRUE(scene->settings.empty());
    EXPECT_TRUE(scene->lights.empty());
}

TEST(SceneLoaderDefaults, IntegralFloatResolutionIsAccepted) {
    Json doc = baseScene();
    doc["camera"]["width"] = 320.0;
    doc["camera"]["height"] = 240;
    auto scene = loadScene(doc, repoSceneOptions());
    EXPECT_EQ(scene->camera.width(), 320);
    EXPECT_EQ(scene->camera.height(), 240);
}

TEST(SceneLoaderDefaults, MaterialDefaults) {
    Json doc = baseScene();
    doc["materials"]["plain"] = {{"type", "diffuse"}};
    doc["shapes"].push_back(
        {{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "glass"}});
    doc["shapes"].push_back(
        {{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "plain"}});
    auto scene = loadScene(doc, repoSceneOptions());
    const auto* glass = dynamic_cast<const Dielectric*>(&scene->material(1));
    ASSERT_NE(glass, nullptr);
    EXPECT_FLOAT_EQ(glass->ior(), 1.5f);
    EXPECT_FALSE(glass->isEmissive());
    const auto* plain = dynamic_cast<const Diffuse*>(&scene->material(2));
    ASSERT_NE(plain, nullptr);
    EXPECT_EQ(plain->albedo(), Color(0.8f));
}

TEST(SceneLoaderDefaults, PointLightsAndEmittersBecomeLights) {
    Json doc = baseScene();
    doc["materials"]["lamp"] = {{"type", "diffuse"}, {"emission", {1, 1, 1}}};
    doc["shapes"].push_back({{"type", "triangle"},
                             {"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}},
                             {"material", "lamp"}});
    doc["lights"] = {{{"type", "point"}, {"position", {0, 2, 0}}, {"intensity", {5, 5, 5}}}};
    auto scene = loadScene(doc, repoSceneOptions());
    ASSERT_EQ(scene->lights.size(), 2u);
    const auto* point = dynamic_cast<const PointLight*>(scene->lights[0].get());
    ASSERT_NE(point, nullptr);
    // Positions are stored relative to the camera.
    Vec3 camera = readVec3(doc["camera"]["position"], "/camera/position");
    EXPECT_EQ(point->position(), Vec3(0, 2, 0) - camera);
    const auto* area = dynamic_cast<const AreaLight*>(scene->lights[1].get());
    ASSERT_NE(area, nullptr);
    EXPECT_EQ(area->prim(), 1u);
}

}  // namespace
}  // namespace caustic

namespace caustic {
namespace {

// Every scene in scenes/ loads from a fresh checkout: the files it names (meshes, the sky, the
// textures) are in the repository's assets folder.
TEST(ExampleScenes, EveryExampleLoadsWithTheRepositorysAssets) {
    size_t examples = 0;
    for (const auto& entry : std::filesystem::directory_iterator(CAUSTIC_SOURCE_DIR "/scenes")) {
        if (entry.path().extension() != ".json") continue;
        ++examples;
        const std::string name = entry.path().stem().string();
        EXPECT_NO_THROW(loadScene(testing::exampleScene(name), testing::repoSceneOptions()))
            << name;
    }
    EXPECT_GE(examples, 9u);
}

}  // namespace
}  // namespace caustic
