// The auto preset's choice of photon maps from what a scene holds (render/presets.h,
// render/scene_traits.h), on the example scenes, and how the choice is reported.
#include <gtest/gtest.h>

#include "core/error.h"
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
    ASSERT_EQ(choice["reasons"].size(), 3u);
    EXPECT_TRUE(choice["reasons"][0].get<std::string>().starts_with("caustics: photon_map;"));
    // The scene's 64 spp cut auto's 16 a pass to 8, for 8 passes.
    EXPECT_TRUE(choice["reasons"][2].get<std::string>().starts_with("spp_per_pass: 8; no target"));
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

// Under a target error auto's passes follow the target: 4 at 2% or more, 8 at 1% or more, its own
// 16 below; without a target, 16. A pass size the scene or the request names stands either way.
TEST(AutoPreset, TakesPassesByItsTarget) {
    auto scene = sceneFromJson(exampleScene("cornell-box", 8, 8));
    const SceneTraits traits = sceneTraits(*scene);
    auto perPass = [&](const Json& request) {
        return mergeSettings(scene->settings, request, &traits)["spp_per_pass"];
    };
    const Json merged = mergeSettings(scene->settings, Json{{"target_error", 0.02}}, &traits);
    EXPECT_EQ(merged["spp_per_pass"], 4);
    EXPECT_EQ(merged["indirect"], "photon_map");
    const Json choice = presetChoice(merged, traits);
    EXPECT_EQ(choice["settings"], (Json{{"indirect", "photon_map"}}));
    EXPECT_TRUE(choice["reasons"].back().get<std::string>().starts_with(
        "spp_per_pass: 4; a target error of 0.02"));
    EXPECT_EQ(perPass(Json{{"target_error", 0.0199}, {"spp", 256}}), 8);
    EXPECT_EQ(perPass(Json{{"target_error", 0.01}, {"spp", 256}}), 8);
    EXPECT_EQ(perPass(Json{{"target_error", 0.005}, {"spp", 256}}), 16);
    // A target of 0 is none.
    EXPECT_EQ(perPass(Json{{"target_error", 0}, {"spp", 256}}), 16);
    // The scene's target counts as the request's does.
    Json withTarget = scene->settings;
    withTarget["target_error"] = 0.05;
    EXPECT_EQ(mergeSettings(withTarget, Json::object(), &traits)["spp_per_pass"], 4);
    // The request's pass size stands, and no reason claims the preset chose it.
    const Json own =
        mergeSettings(scene->settings, Json{{"target_error", 0.02}, {"spp_per_pass", 5}}, &traits);
    EXPECT_EQ(own["spp_per_pass"], 5);
    const Json ownChoice = presetChoice(own, traits);
    for (const Json& reason : ownChoice["reasons"])
        EXPECT_FALSE(reason.get<std::string>().starts_with("spp_per_pass"));
    // A target that is no number is refused by parseSettings, at its path; the choice, made
    // before that, takes it for none and does not throw.
    const Json bad = mergeSettings(scene->settings, Json{{"target_error", "1%"}}, &traits);
    EXPECT_NO_THROW(presetChoice(bad, traits));
    try {
        parseSettings(bad, "/settings");
        ADD_FAILURE() << "a string target_error was accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), "/settings/target_error");
    }
    // An spp too small for 8 passes of 4 still gets its 8 passes.
    EXPECT_EQ(perPass(Json{{"target_error", 0.02}, {"spp", 16}}), 2);
}

}  // namespace
}  // namespace caustic
