#include "render_options.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "command_line.h"
#include "render/settings.h"

namespace caustic {
namespace {

std::string joined(const std::vector<std::string>& items) {
    std::string text;
    for (const std::string& item : items) text += (text.empty() ? "" : ", ") + item;
    return text;
}

// The type column of a setting's --help line: its type and range or choices.
std::string settingTypeText(const SettingSpec& spec) {
    switch (spec.type) {
        case SettingType::Integer:
        case SettingType::Number:
            return cli::rangeText(spec.min, spec.max, spec.type == SettingType::Integer);
        case SettingType::Boolean:
            return "true|false";
        case SettingType::String:
            if (!spec.choices.empty()) {
                std::string choices = joined(spec.choices);
                std::replace(choices.begin(), choices.end(), ',', '|');
                choices.erase(std::remove(choices.begin(), choices.end(), ' '), choices.end());
                return choices;
            }
            return "TEXT";
    }
    return "VALUE";
}

// The description of a setting's --help line: the table's, with its unit and integrators.
std::string settingHelp(const SettingSpec& spec) {
    std::string help = spec.description;
    if (!spec.unit.empty()) help += " Unit: " + spec.unit + ".";
    if (!spec.integrators.empty()) help += " Read by " + joined(spec.integrators) + ".";
    return help;
}

// Options parsed now, not after the whole command line: overrides then apply in the order they
// were given, so `--set spp=4 --spp 8` renders 8 spp and `--spp 8 --set spp=4` renders 4.
void addSettingOptions(CLI::App& render, Json& overrides) {
    render
        .add_option_function<std::string>(
            "--set",
            [&overrides](const std::string& keyValue) {
                size_t eq = keyValue.find('=');
                if (eq == std::string::npos || eq == 0)
                    throw CLI::ValidationError("--set",
                                               "expected key=value, got \"" + keyValue + "\"");
                overrides[keyValue.substr(0, eq)] = parseSettingValue(keyValue.substr(eq + 1));
            },
            "Overrides a render setting; the value is JSON (spp=64, integrator=raycast, "
            "light_sampling=false). Repeatable; the options below set one setting each")
        ->type_name("KEY=VALUE")
        ->trigger_on_parse();
    for (const SettingSpec& spec : settingSpecs()) {
        // The value goes into the overrides as --set puts it, so that parseSettings checks it and
        // an error reads the same either way.
        render
            .add_option_function<std::string>(
                settingOptionName(spec.name),
                [&overrides, name = spec.name](const std::string& value) {
                    overrides[name] = parseSettingValue(value);
                },
                settingHelp(spec))
            ->type_name(settingTypeText(spec))
            ->default_str(settingValueText(spec.defaultValue))
            ->group(
                "Render settings (over the scene's own; the default is the scene's, else the "
                "one shown)")
            ->trigger_on_parse();
    }
}

}  // namespace

std::string settingValueText(const Json& value) {
    if (value.is_string()) return value.get<std::string>();
    if (value.is_number()) return cli::formatNumber(value.get<double>());
    return value.dump();
}

std::string settingOptionName(const std::string& setting) {
    std::string name = "--" + setting;
    std::replace(name.begin(), name.end(), '_', '-');
    return name;
}

CLI::App* addRenderCommand(CLI::App& app, RenderOptions& options) {
    CLI::App* render = app.add_subcommand("render", "Renders a scene to PNG and EXR images.");
    render
        ->add_option("scene", options.scene,
                     "A scene JSON file, a glTF model (.glb, or .gltf with its files beside it), "
                     "or the name of an example scene in scenes/ (cornell-spheres, cornell-box, "
                     "bunny, caustic-glass, meshes, indirect)")
        ->type_name("FILE|NAME")
        ->required();
    render
        ->add_option("-o,--output", options.outputs,
                     ".png (8-bit sRGB, after exposure) or .exr (linear float); repeatable")
        ->type_name("FILE")
        ->required()
        ->allow_extra_args(false)
        ->check(
            [](const std::string& file) {
                std::string ext = std::filesystem::path(file).extension().string();
                return ext == ".png" || ext == ".exr"
                           ? std::string()
                           : "must end in .png or .exr, got \"" + file + "\"";
            },
            "");
    options.assets = CAUSTIC_DEFAULT_ASSETS_DIR;
    render->add_option("--assets", options.assets, "The folder mesh file names resolve in")
        ->type_name("DIR")
        ->envname("CAUSTIC_ASSETS")
        ->capture_default_str();
    render
        ->add_option("--stats", options.stats,
                     "Writes the resolved settings and the render's stats (time per phase, rays, "
                     "error, memory by component) as JSON")
        ->type_name("FILE");
    render
        ->add_flag_callback(
            "--progress", [&options] { options.progress = 1; },
            "Draws a progress bar on stderr (default: when stderr is a terminal)")
        ->trigger_on_parse();
    render
        ->add_flag_callback(
            "--no-progress", [&options] { options.progress = 0; }, "Draws no progress bar")
        ->trigger_on_parse();
    render->add_flag("-q,--quiet", options.quiet, "Prints neither progress nor the summary line");
    render
        ->add_option_function<std::string>(
            "--camera",
            [&options](const std::string& camera) {
                const bool index =
                    !camera.empty() && camera.find_first_not_of("0123456789") == std::string::npos;
                options.gltf["camera"] = camera == "auto"
                                             ? nlohmann::json{{"auto", nlohmann::json::object()}}
                                         : index ? nlohmann::json{{"gltf", std::stoi(camera)}}
                                                 : nlohmann::json{{"gltf", camera}};
            },
            "glTF only: the file's camera to render through, by index or name, or auto (framing "
            "the scene; default: the file's first camera, else auto)")
        ->type_name("INDEX|NAME|auto");
    render
        ->add_option_function<std::string>(
            "--environment",
            [&options](const std::string& environment) {
                options.gltf["environment"] =
                    environment == "none" ? nlohmann::json() : nlohmann::json::parse(environment);
            },
            "glTF only: the environment as scene JSON ('{\"file\": \"sky.exr\"}'), or none "
            "(default: the file's lights alone, or a white environment when it has none)")
        ->type_name("JSON|none")
        ->check(
            [](const std::string& e) {
                return e == "none" || nlohmann::json::accept(e)
                           ? std::string()
                           : "must be JSON or none, got \"" + e + "\"";
            },
            "");
    addSettingOptions(*render, options.overrides);
    return render;
}

}  // namespace caustic
