// `caustic settings`: every render setting from the settings table, as JSON (the schema that
// GET /api/settings serves) or, with --markdown, as the reference page docs/settings.md.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace caustic {

struct SettingsOptions {
    bool markdown = false;
};

CLI::App* addSettingsCommand(CLI::App& app, SettingsOptions& options);
int runSettings(const SettingsOptions& options);

/// docs/settings.md: the settings table and the presets as Markdown. CI compares the committed page
/// with it (tests/docs/), so the reference cannot drift from the table.
std::string settingsMarkdown();

}  // namespace caustic
