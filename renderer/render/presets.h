// Presets: named partial settings objects (`"preset": "preview"`), chosen from the speed/accuracy
// study (docs/study/README.md). A preset sits between the scene's own settings and the request's:
// it replaces the scene's values for what it sets, and every setting the request names replaces
// the preset's.
//
// `auto` and the quality presets take photon maps where the scene needs them (sceneMaps): a caustic
// map for mirrors and smooth glass lit by local lights, an indirect map for diffuse interreflection
// under local lights. Their bias is in the error estimate (film/film.h), so a target error stops
// them as truly as an unbiased render.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace caustic {

struct SceneTraits;

struct Preset {
    std::string name;
    std::string description;
    nlohmann::json settings;  ///< The settings it sets, by JSON name, whatever the scene.
    bool sceneMaps = false;   ///< Also the photon maps the scene needs (photonMapsFor).
    /// Set over `settings` by the render's target error (its own, the scene's or the request's):
    /// [{"target_error": t, "settings": {...}}, ...] by falling t, the first with t at most the
    /// target. Smaller passes for looser targets, so that a render stops near the pass that
    /// reaches its target rather than at its floor (render/stopping.h).
    nlohmann::json underTarget = nlohmann::json::array();
};

/// What a preset chose for one scene beyond its fixed settings, and why: {"settings": {...},
/// "reasons": ["...", ...]}.
nlohmann::json photonMapsFor(const SceneTraits& traits);

/// Every preset, fastest first.
const std::vector<Preset>& presets();
/// The settings of preset `name`, with the photon maps `traits` need where the preset takes them
/// (none without traits) and its `underTarget` settings for `targetError` (0: none); an empty
/// object for "none" or a name that is no preset (which parseSettings then refuses at .../preset).
nlohmann::json presetSettings(const nlohmann::json& name, const SceneTraits* traits = nullptr,
                              double targetError = 0);
/// A preset's pass size `perPass` beside an spp it did not set: cut to leave that spp the 8
/// passes an error estimate needs, as far as it can (`--preset final --spp 64` renders 8 of 8).
nlohmann::json presetPassSize(const nlohmann::json& perPass, const nlohmann::json& spp);
/// What the preset `merged` (settings after mergeSettings) names chose for a scene of `traits`
/// and why (photonMapsFor), with "preset": its name; a choice the merged settings replaced is
/// left out of "settings" and its reason says so. Null for "none", a preset that takes no maps,
/// or no preset.
nlohmann::json presetChoice(const nlohmann::json& merged, const SceneTraits& traits);

}  // namespace caustic
