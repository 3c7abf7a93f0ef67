// A render's stats list what its scene built because it uses it, with the time and bytes each
// took: an environment image's sampling density, the texture system, tangent frames, the light
// tables. A scene that uses none of them builds none.
#include <gtest/gtest.h>

#include <set>

#include "render/renderer.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using nlohmann::json;

std::set<std::string> partNames(const RenderStats& stats) {
    std::set<std::string> names;
    for (const BuiltPart& p : stats.built) names.insert(p.part);
    return names;
}

const BuiltPart& part(const RenderStats& stats, const std::string& name) {
    for (const BuiltPart& p : stats.built)
        if (p.part == name) return p;
    throw std::runtime_error("no built part " + name);
}

TEST(BuiltParts, AnUntexturedSceneWithoutEnvironmentBuildsOnlyItsLightTables) {
    auto scene = testing::sceneFromJson(testing::exampleScene("cornell-spheres", 16, 16));
    const RenderStats stats =
        render(*scene, testing::settingsFrom({{"integrator", "path"}, {"spp", 1}})).stats;
    EXPECT_EQ(partNames(stats), std::set<std::string>{"light tables"});
    EXPECT_GT(part(stats, "light tables").bytes, 0u);
    const json j = stats.toJson()["built"];
    ASSERT_EQ(j.size(), 1u);
    EXPECT_EQ(j[0]["part"], "light tables");
    for (const char* key : {"seconds", "bytes", "count"}) EXPECT_TRUE(j[0].contains(key)) << key;
}

TEST(BuiltParts, ASceneListsItsEnvironmentTexturesAndTangentFrames) {
    const json doc = json::parse(R"({
      "camera": {"position": [0, 0.5, 3], "look_at": [0, 0.4, 0], "width": 16, "height": 16},
      "materials": {
        "cow": {"type": "metallic_roughness", "metallic": 0, "roughness": 0.5,
                "base_color_texture": "spot-pattern.png", "normal_texture": "tiles-normal.png"},
        "floor": {"type": "metallic_roughness", "metallic": 0, "base_color_texture": "tiles.png"}
      },
      "shapes": [
        {"type": "mesh", "file": "spot.obj", "material": "cow"},
        {"type": "quad", "origin": [-2, 0, 2], "u": [4, 0, 0], "v": [0, 0, -4],
         "material": "floor"}
      ],
      "environment": {"file": "sky.exr"}
    })");
    auto scene = testing::sceneFromJson(doc);
    const RenderStats stats =
        render(*scene, testing::settingsFrom({{"integrator", "path"}, {"spp", 1}})).stats;
    EXPECT_EQ(partNames(stats), (std::set<std::string>{"environment distribution", "texture system",
                                                       "tangent frames", "light tables"}));
    EXPECT_EQ(part(stats, "environment distribution").bytes, scene->environmentBytes);
    EXPECT_EQ(part(stats, "texture system").count, 3);  // three textures, one store
    EXPECT_EQ(part(stats, "texture system").bytes, scene->textureBytes);
    // MikkTSpace's tangent (and sign) per vertex of the one normal-mapped mesh.
    const BuiltPart& tangents = part(stats, "tangent frames");
    EXPECT_EQ(tangents.count, 1);
    EXPECT_EQ(tangents.bytes, scene->geometry.positions().size() * 16);
    for (const BuiltPart& p : stats.built) EXPECT_GE(p.seconds, 0.0) << p.part;
}

}  // namespace
}  // namespace caustic
