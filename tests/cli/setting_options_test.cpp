// `caustic render`'s options generated from the settings table: one per setting, listed by --help,
// checked exactly as --set is, applied in the order given.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli/cli_run.h"
#include "render/presets.h"
#include "render/settings.h"

namespace {

namespace fs = std::filesystem;
using caustic::Json;
using caustic::SettingSpec;
using caustic::settingSpecs;
using caustic::SettingType;
using caustic::testing::CliRun;
using caustic::testing::kTinyScene;
using caustic::testing::runCli;
using caustic::testing::writeFile;

using SettingOptions = caustic::testing::CliTest;

// The documented spelling: the setting's name with '-' for '_'.
std::string optionName(const std::string& setting) {
    std::string name = "--" + setting;
    std::replace(name.begin(), name.end(), '_', '-');
    return name;
}

// A value the settings table refuses: out of range, not a boolean, not a choice.
std::string badValue(const SettingSpec& spec) {
    switch (spec.type) {
        case SettingType::Integer:
        case SettingType::Number:
            return Json(spec.max * 2 + 1).dump();
        case SettingType::Boolean:
            return "maybe";
        case SettingType::String:
            return spec.choices.empty() ? "1" : "no-such-" + spec.name;
    }
    return "";
}

Json readJson(const fs::path& file) {
    std::ifstream in(file);
    return Json::parse(in);
}

TEST_F(SettingOptions, HelpListsEverySetting) {
    CliRun r = runCli("render --help");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (const SettingSpec& spec : settingSpecs()) {
        EXPECT_NE(r.output.find("  " + optionName(spec.name) + " "), std::string::npos)
            << spec.name << " has no option in:\n"
            << r.output;
        EXPECT_NE(r.output.find(spec.description), std::string::npos) << spec.name;
    }
}

TEST_F(SettingOptions, BadValueGivesTheSameErrorAsSet) {
    fs::path dir = tempDir();
    writeFile(dir / "tiny.json", kTinyScene);
    const std::string render =
        "render " + (dir / "tiny.json").string() + " -o " + (dir / "x.png").string() + " ";
    for (const SettingSpec& spec : settingSpecs()) {
        const std::string bad = badValue(spec);
        CliRun option = runCli(render + optionName(spec.name) + " '" + bad + "'");
        CliRun set = runCli(render + "--set '" + spec.name + "=" + bad + "'");
        EXPECT_EQ(option.exitCode, 2) << spec.name << ": " << option.output;
        EXPECT_EQ(option.output, set.output) << spec.name;
        EXPECT_NE(option.output.find(": /settings/" + spec.name + ": "), std::string::npos)
            << option.output;
    }
    EXPECT_FALSE(fs::exists(dir / "x.png"));
}

TEST_F(SettingOptions, ValuesReachTheRenderInTheOrderGiven) {
    fs::path dir = tempDir();
    writeFile(dir / "tiny.json", kTinyScene);
    const std::string render = "render " + (dir / "tiny.json").string() + " -o " +
                               (dir / "x.png").string() + " --quiet --stats " +
                               (dir / "stats.json").string() + " ";

    // (The stats list the settings the chosen integrator reads: path reads light_sampling.)
    CliRun r = runCli(render + "--integrator raycast --integrator path --light-sampling false " +
                      "--exposure -1.5 --set spp=3 --spp 2");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    Json settings = readJson(dir / "stats.json")["settings"];
    EXPECT_EQ(settings["integrator"], "path");
    EXPECT_EQ(settings["light_sampling"], false);
    EXPECT_EQ(settings["exposure"], -1.5);
    EXPECT_EQ(settings["spp"], 2);

    r = runCli(render + "--spp 2 --set spp=3");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(readJson(dir / "stats.json")["settings"]["spp"], 3);
}

TEST_F(SettingOptions, APresetSetsWhatTheOtherOptionsDoNot) {
    fs::path dir = tempDir();
    writeFile(dir / "tiny.json", kTinyScene);
    const std::string render = "render " + (dir / "tiny.json").string() + " -o " +
                               (dir / "x.png").string() + " --quiet --stats " +
                               (dir / "stats.json").string() + " ";
    CliRun r = runCli(render + "--preset draft --seed 3");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    Json settings = readJson(dir / "stats.json")["settings"];
    EXPECT_EQ(settings["preset"], "draft");
    const Json draft = caustic::presetSettings("draft");
    for (const auto& [key, value] : draft.items()) EXPECT_EQ(settings[key], value) << key;
    EXPECT_EQ(settings["seed"], 3);
    // An option beside the preset wins, whatever the order.
    r = runCli(render + "--spp 2 --preset draft");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(readJson(dir / "stats.json")["settings"]["spp"], 2);
    r = runCli(render + "--preset best");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.output.find("best"), std::string::npos) << r.output;
}

TEST_F(SettingOptions, SettingsCommandPrintsTheTable) {
    CliRun r = runCli("settings");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    Json table = Json::parse(r.output);
    for (const SettingSpec& spec : settingSpecs()) EXPECT_TRUE(table.contains(spec.name));
}

}  // namespace
