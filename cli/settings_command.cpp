#include "settings_command.h"

#include <iostream>
#include <sstream>

#include "command_line.h"
#include "render/presets.h"
#include "render/settings.h"
#include "render_options.h"

namespace caustic {
namespace {

// A table cell: pipes escaped, so that a description cannot split its row.
std::string cell(const std::string& text) {
    std::string out;
    for (char c : text) {
        if (c == '|') out += '\\';
        out += c;
    }
    return out;
}

std::string code(const std::string& text) {
    return "`" + text + "`";
}

// The values a setting takes: its range and unit, or its choices.
std::string rangeText(const SettingSpec& spec) {
    std::string text;
    if (spec.type == SettingType::Integer || spec.type == SettingType::Number)
        text = cli::formatNumber(spec.min) + " – " + cli::formatNumber(spec.max);
    else if (spec.type == SettingType::Boolean)
        text = "`true`, `false`";
    for (const std::string& choice : spec.choices)
        text += (text.empty() ? "" : ", ") + code(choice);
    if (!spec.unit.empty()) text += " " + spec.unit;
    // The render service's flag that caps it (server/jobs/submission.cpp).
    static const char* const flags[] = {"", "--max-spp", "--max-photons", "--max-time-limit",
                                        "--max-memory-mib"};
    if (spec.cap != SettingCap::None)
        text += "; at most the service's " + code(flags[static_cast<int>(spec.cap)]);
    return text;
}

// Which integrators read it, and for path's photon-map settings, beside which map.
std::string readByText(const SettingSpec& spec) {
    if (spec.integrators.empty()) return "all";
    std::string text;
    for (const std::string& name : spec.integrators) {
        text += (text.empty() ? "" : ", ") + code(name);
        if (name != "path" || spec.pathMaps == 0) continue;
        std::string maps;
        if (spec.pathMaps & SettingSpec::kCausticMap) maps = "`caustics=photon_map`";
        if (spec.pathMaps & SettingSpec::kIndirectMap)
            maps += (maps.empty() ? "" : " or ") + std::string("`indirect=photon_map`");
        text += " (with " + maps + ")";
    }
    return text;
}

std::string presetText(const Json& settings) {
    std::string text;
    for (auto it = settings.begin(); it != settings.end(); ++it)
        text += (text.empty() ? "" : ", ") + code(it.key() + "=" + settingValueText(it.value()));
    return text;
}

}  // namespace

std::string settingsMarkdown() {
    std::ostringstream md;
    md << "# Render settings\n\n"
          "<!-- Generated from renderer/render/settings_table.cpp by `caustic settings "
          "--markdown > docs/settings.md`; do not edit: CI fails when this page differs from "
          "what the table generates. -->\n\n"
          "Every setting of a render, from the one table that parses and validates them. A "
          "setting goes in a scene's `settings`, in a job's `settings` (HTTP, the web page's "
          "form) or on the command line (`--spp 64`, or `--set spp=64`); a job's or the command "
          "line's replace the scene's, and a setting given nowhere takes its default. Every "
          "setting is accepted whatever the integrator; \"read by\" says which integrators use "
          "it. `caustic settings` and `GET /api/settings` give the same table as JSON. What "
          "passes, error estimates and stopping rules mean: "
          "[speed and accuracy](speed-and-accuracy.md); which integrator to choose: "
          "[integrators](integrators.md).\n\n"
          "| setting | type | default | values | read by | meaning |\n"
          "|---|---|---|---|---|---|\n";
    for (const SettingSpec& spec : settingSpecs())
        md << "| " << code(spec.name) << " (" << code(settingOptionName(spec.name)) << ") | "
           << toString(spec.type) << " | " << code(settingValueText(spec.defaultValue)) << " | "
           << cell(rangeText(spec)) << " | " << readByText(spec) << " | " << cell(spec.description)
           << " |\n";
    md << "\n## Presets\n\n"
          "`preset` names settings chosen from the speed/accuracy study. A preset replaces the "
          "scene's own values for what it sets, and every setting given beside it replaces the "
          "preset's.\n\n"
          "| preset | sets | for |\n"
          "|---|---|---|\n";
    for (const Preset& p : presets())
        md << "| " << code(p.name) << " | " << presetText(p.settings) << " | "
           << cell(p.description) << " |\n";
    return md.str();
}

CLI::App* addSettingsCommand(CLI::App& app, SettingsOptions& options) {
    CLI::App* settings = app.add_subcommand(
        "settings",
        "Prints every render setting as JSON: type, default, range, unit, meaning, the presets.");
    settings->add_flag("--markdown", options.markdown,
                       "Prints the reference page docs/settings.md instead");
    return settings;
}

int runSettings(const SettingsOptions& options) {
    if (options.markdown)
        std::cout << settingsMarkdown();
    else
        std::cout << settingsSchemaJson().dump(2) << "\n";
    return 0;
}

}  // namespace caustic
