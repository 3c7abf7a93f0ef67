// The auto preset's choice of photon maps from what a scene holds (render/presets.h,
// render/scene_traits.h), on the example scenes, and how the choice is reported.
#include <gtest/gtest.h>

#include "render/presets.h"
#include "render/scene_traits.h"
#include "render/settings.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using testing::exampleScene;
using testing::sceneFromJson;

Json mapsOf(const std::string& name) {
    const SceneTraits traits = sceneTraits(*sceneFromJson(exampleScene(name, 8, 8)));
    return photonMapsFor(traits)["settings"];
}

TEST(AutoPreset, TakesTheMapsTheSceneNeeds) {
    // A closed diffuse room lit by a lamp: interreflection, no caustics.
    EXPECT_EQ(mapsOf("cornell-box"), (Json{{"indirect", "photon_map"}}));
    // Glass and a mirror under the lamp: caustics too.
    EXPECT_EQ(mapsOf("cornell-spheres"),
              (Json{{"caustics", "photon_map"}, {"indirect", "photon_map"}}));
    // Spot lights on glass and diffuse surfaces.
    EXPECT_EQ(mapsOf("stage-lights"),
              (Json{{"caustics", "photon_map"}, {"indirect", "photon_map"}}));
    // Lit by the sky: photons would spread over the whole ground; no smooth glass either.
    EXPECT_EQ(mapsOf("outdoor-metals"), Json::object());
}

TEST(AutoPreset, SaysWhatItChoseAndWhy) {
    auto scene = sceneFromJson(exampleScene("cornell-spheres", 8, 8));
    const SceneTraits traits = sceneTraits(*scene);
    EXPECT_TRUE(traits.specular);
    EXPECT_TRUE(traits.diffuse);
    EXPECT_TRUE(traits.localLight());
    Json merged = mergeSettings(scene->settings, Json::object(), &traits);
    EXPECT_EQ(merged["caustics"], "photon_map");
    Json choice = presetChoice(merged, traits);
    EXPECT_EQ(choice["preset"], "auto");
    EXPECT_EQ(choice["settings"], (Json{{"caustics", "photon_map"}, {"indirect", "photon_map"}}));
    ASSERT_EQ(choice["reasons"].size(), 2u);
    EXPECT_TRUE(choice["reasons"][0].get<std::string>().starts_with("caustics: photon_map;"));
    // A request's own choice stands, and the reason says the preset's was replaced.
    merged = mergeSettings(scene->settings, Json{{"caustics", "paths"}}, &traits);
    EXPECT_EQ(merged["caustics"], "paths");
    choice = presetChoice(merged, traits);
    EXPECT_EQ(choice["settings"], (Json{{"indirect", "photon_map"}}));
    EXPECT_NE(choice["reasons"][0].get<std::string>().find("replaced by caustics=\"paths\""),
              std::string::npos);
    // The quality presets take the maps too; none takes nothing and says nothing.
    merged = mergeSettings(scene->settings, Json{{"preset", "final"}}, &traits);
    EXPECT_EQ(merged["indirect"], "photon_map");
    merged = mergeSettings(scene->settings, Json{{"preset", "none"}}, &traits);
    EXPECT_FALSE(merged.contains("indirect"));
    EXPECT_TRUE(presetChoice(merged, traits).is_null());
}

}  // namespace
}  // namespace caustic
