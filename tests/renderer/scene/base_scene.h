// A small valid scene, and ways to break it in one place, shared by the scene loader tests.
#pragma once

#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "scene/json_reader.h"
#include "scene/scene.h"

namespace caustic::testing {

// A small valid scene that each case breaks in one place.
inline Json baseScene() {
    return Json::parse(R"({
        "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
        "materials": {
            "white": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]},
            "glass": {"type": "dielectric"}
        },
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white"}]
    })");
}

// The base scene with the value at a JSON pointer set (or added), or removed.
inline Json patched(const std::string& pointer, const Json& value) {
    Json doc = baseScene();
    doc[Json::json_pointer(pointer)] = value;
    return doc;
}

inline Json without(const std::string& pointer) {
    Json::json_pointer p(pointer);
    Json doc = baseScene();
    doc[p.parent_pointer()].erase(p.back());
    return doc;
}

// Expects loading `doc` to fail with exactly this path and message.
inline void expectSceneError(const Json& doc, const std::string& path, const std::string& message,
                             const SceneOptions& options) {
    try {
        loadScene(doc, options);
        ADD_FAILURE() << "scene loaded; expected \"" << path << ": " << message << "\"";
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), path);
        EXPECT_EQ(e.message(), message);
        EXPECT_EQ(std::string(e.what()), (path.empty() ? "/" : path) + ": " + message);
    }
}

}  // namespace caustic::testing
