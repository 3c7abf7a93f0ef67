// `caustic render`'s command line: its options, and one option per render setting generated from
// the settings table (renderer/render/settings.h), so that a setting added there is an option here.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace CLI {
class App;
}

namespace caustic {

/// What `caustic render` was asked to do.
struct RenderOptions {
    std::string scene;                 ///< A scene file, or the name of an example scene.
    std::vector<std::string> outputs;  ///< Images to write, each .png or .exr.
    /// Settings over the scene's: from --set and the setting options (--spp 64), as JSON values
    /// not yet validated (parseSettings does that). The last one given wins.
    nlohmann::json overrides = nlohmann::json::object();
    std::string assets;  ///< The folder mesh files resolve in.
    std::string stats;   ///< Where to write the settings and stats as JSON; empty for nowhere.
    int progress = -1;   ///< 1 draws a progress bar, 0 does not, -1 when stderr is a terminal.
    /// For a glTF file: the overrides of a job's "scene" object (docs/gltf.md), from --camera and
    /// --environment.
    nlohmann::json gltf = nlohmann::json::object();
    bool quiet = false;  ///< No progress bar and no summary line.
};

/// The option of a render setting: "light_sampling" is --light-sampling.
std::string settingOptionName(const std::string& setting);
/// A setting's value as it is typed on the command line: strings without quotes, numbers short.
std::string settingValueText(const nlohmann::json& value);

/// Adds the `render` subcommand to `app`. Parsing fills `options`, which must outlive it.
CLI::App* addRenderCommand(CLI::App& app, RenderOptions& options);

}  // namespace caustic
