// Presets: named partial settings objects (`"preset": "preview"`), chosen from the speed/accuracy
// study (docs/study/README.md). A preset sits between the scene's own settings and the request's:
// it replaces the scene's values for what it sets, and every setting the request names replaces
// the preset's.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace caustic {

struct Preset {
    std::string name;
    std::string description;
    nlohmann::json settings;  ///< The settings it sets, by JSON name.
};

/// Every preset, fastest first.
const std::vector<Preset>& presets();
/// The settings of preset `name`; an empty object for "none" or a name that is no preset (which
/// parseSettings then refuses at .../preset).
nlohmann::json presetSettings(const nlohmann::json& name);

}  // namespace caustic
