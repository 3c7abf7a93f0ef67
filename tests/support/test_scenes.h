// Helpers shared by renderer tests: load scenes from JSON text, render them small.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "render/renderer.h"
#include "scene/scene.h"

namespace caustic::testing {

/// Options with the repository's assets folder.
inline SceneOptions repoSceneOptions() {
    SceneOptions o;
    o.assetsDir = CAUSTIC_SOURCE_DIR "/assets/meshes";
    return o;
}

inline std::unique_ptr<Scene> sceneFromJson(const nlohmann::json& doc) {
    return loadScene(doc, repoSceneOptions());
}

/// An example scene from scenes/, optionally resized.
inline nlohmann::json exampleScene(const std::string& name, int width = 0, int height = 0) {
    nlohmann::json doc = readJsonFile(CAUSTIC_SOURCE_DIR "/scenes/" + name + ".json");
    if (width > 0) doc["camera"]["width"] = width;
    if (height > 0) doc["camera"]["height"] = height;
    return doc;
}

/// Settings from JSON over the defaults, with the scene's own settings ignored.
inline RenderSettings settingsFrom(const nlohmann::json& j) {
    return parseSettings(j);
}

}  // namespace caustic::testing
