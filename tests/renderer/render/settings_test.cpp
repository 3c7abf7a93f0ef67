// Render settings: exact error messages, merging, command-line values, and the automatic samples
// per pass. settings_table_test.cpp checks the table, defaults and JSON round trips.
#include "render/settings.h"

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "accel/accelerator.h"
#include "core/error.h"
#include "integrators/integrator.h"
#include "render/integrator_factory.h"
#include "render/presets.h"

namespace caustic {
namespace {

std::string joined(const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

std::vector<std::string> specNames() {
    std::vector<std::string> names;
    for (const SettingSpec& s : settingSpecs()) names.push_back(s.name);
    return names;
}

void expectSettingsError(const Json& settings, const std::string& path,
                         const std::string& message) {
    try {
        parseSettings(settings);
        ADD_FAILURE() << "settings accepted: " << settings.dump();
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), path);
        EXPECT_EQ(e.message(), message);
    }
}

#define EXPECT_SETTINGS_ERROR(settings, path, message)  \
    do {                                                \
        SCOPED_TRACE(Json(settings).dump());            \
        expectSettingsError((settings), path, message); \
    } while (0)

TEST(SettingsErrors, UnknownSettingListsValidOnes) {
    EXPECT_SETTINGS_ERROR((Json{{"samples", 16}}), "/settings/samples",
                          "unknown setting; valid settings: " + joined(specNames()));
    try {
        parseSettings(Json{{"samples", 16}});
    } catch (const InputError& e) {
        for (const char* name : {"integrator", "spp", "spp_per_pass", "max_depth", "seed"})
            EXPECT_NE(e.message().find(name), std::string::npos) << name;
    }
}

TEST(SettingsErrors, SppOutOfRange) {
    EXPECT_SETTINGS_ERROR((Json{{"spp", 0}}), "/settings/spp", "must be in [1, 1000000], got 0");
    EXPECT_SETTINGS_ERROR((Json{{"spp", -4}}), "/settings/spp", "must be in [1, 1000000], got -4");
    EXPECT_SETTINGS_ERROR((Json{{"spp", 1000001}}), "/settings/spp",
                          "must be in [1, 1000000], got 1000001");
    EXPECT_EQ(parseSettings(Json{{"spp", 1000000}}).spp, 1000000);
}

TEST(SettingsErrors, OtherRanges) {
    EXPECT_SETTINGS_ERROR((Json{{"max_depth", 0}}), "/settings/max_depth",
                          "must be in [1, 1000000], got 0");
    EXPECT_SETTINGS_ERROR((Json{{"threads", 1025}}), "/settings/threads",
                          "must be in [0, 1024], got 1025");
    EXPECT_SETTINGS_ERROR((Json{{"seed", -1}}), "/settings/seed",
                          "must be in [0, 9007199254740991], got -1");
    EXPECT_SETTINGS_ERROR((Json{{"time_limit", -0.5}}), "/settings/time_limit",
                          "must be in [0, 1000000], got -0.5");
    EXPECT_SETTINGS_ERROR((Json{{"target_error", 1.5}}), "/settings/target_error",
                          "must be in [0, 1], got 1.5");
    EXPECT_SETTINGS_ERROR((Json{{"exposure", -20.5}}), "/settings/exposure",
                          "must be in [-20, 20], got -20.5");
    EXPECT_SETTINGS_ERROR((Json{{"spp_per_pass", -1}}), "/settings/spp_per_pass",
                          "must be in [0, 1000000], got -1");
}

TEST(SettingsErrors, WrongTypes) {
    EXPECT_SETTINGS_ERROR((Json{{"spp", "16"}}), "/settings/spp",
                          "expected an integer, got a string");
    EXPECT_SETTINGS_ERROR((Json{{"spp", true}}), "/settings/spp",
                          "expected an integer, got a boolean");
    EXPECT_SETTINGS_ERROR((Json{{"seed", nullptr}}), "/settings/seed",
                          "expected an integer, got null");
    EXPECT_SETTINGS_ERROR((Json{{"integrator", 3}}), "/settings/integrator",
                          "expected a string, got a number");
    EXPECT_SETTINGS_ERROR((Json{{"exposure", "1"}}), "/settings/exposure",
                          "expected a number, got a string");
    EXPECT_SETTINGS_ERROR((Json{{"time_limit", Json::array({1})}}), "/settings/time_limit",
                          "expected a number, got an array");
}

TEST(SettingsErrors, IntegerGivenAFraction) {
    EXPECT_SETTINGS_ERROR((Json{{"spp", 2.5}}), "/settings/spp",
                          "expected an integer, got a fraction");
    EXPECT_SETTINGS_ERROR((Json{{"max_depth", 7.25}}), "/settings/max_depth",
                          "expected an integer, got a fraction");
    // An integral value written as a float is an integer.
    EXPECT_EQ(parseSettings(Json{{"spp", 32.0}}).spp, 32);
}

TEST(SettingsErrors, NonFiniteAndHugeNumbers) {
    EXPECT_SETTINGS_ERROR((Json{{"time_limit", std::numeric_limits<double>::infinity()}}),
                          "/settings/time_limit", "must be a finite number");
    EXPECT_SETTINGS_ERROR((Json{{"exposure", std::numeric_limits<double>::quiet_NaN()}}),
                          "/settings/exposure", "must be a finite number");
    EXPECT_SETTINGS_ERROR((Json{{"spp", std::numeric_limits<double>::infinity()}}), "/settings/spp",
                          "must be a finite number");
    // Not wrapped around to -1.
    EXPECT_SETTINGS_ERROR((Json{{"seed", std::numeric_limits<uint64_t>::max()}}), "/settings/seed",
                          "is out of the range of an integer (|x| <= 2^53)");
    EXPECT_EQ(parseSettings(Json{{"seed", 9007199254740991}}).seed, 9007199254740991u);
}

TEST(SettingsErrors, UnknownIntegratorListsValidNames) {
    EXPECT_SETTINGS_ERROR((Json{{"integrator", "bogus"}}), "/settings/integrator",
                          "unknown value \"bogus\"; valid: " + joined(integratorNames()));
    EXPECT_SETTINGS_ERROR((Json{{"accelerator", "octree"}}), "/settings/accelerator",
                          "unknown value \"octree\"; valid: " + joined(acceleratorNames()));
    for (const std::string& name : integratorNames())
        EXPECT_EQ(parseSettings(Json{{"integrator", name}}).integrator, name);
}

TEST(SettingsErrors, NotAnObject) {
    EXPECT_SETTINGS_ERROR(Json::array(), "/settings", "expected an object, got an array");
    EXPECT_SETTINGS_ERROR(Json("spp=16"), "/settings", "expected an object, got a string");
}

TEST(SettingsErrors, PathIsConfigurable) {
    try {
        parseSettings(Json{{"spp", 0}}, "/jobs/0/settings");
        ADD_FAILURE() << "spp 0 accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), "/jobs/0/settings/spp");
        EXPECT_EQ(std::string(e.what()), "/jobs/0/settings/spp: must be in [1, 1000000], got 0");
    }
}

TEST(SettingsErrors, SppPerPassAboveSpp) {
    EXPECT_SETTINGS_ERROR((Json{{"spp", 16}, {"spp_per_pass", 32}}), "/settings/spp_per_pass",
                          "must be at most spp (16)");
    // Against the default spp too.
    EXPECT_SETTINGS_ERROR((Json{{"spp_per_pass", 17}}), "/settings/spp_per_pass",
                          "must be at most spp (16)");
    EXPECT_EQ(parseSettings(Json{{"spp", 16}, {"spp_per_pass", 16}}).sppPerPass, 16);
}

TEST(SettingsMerge, OverridesKeyByKey) {
    Json defaults{{"preset", "none"}, {"integrator", "whitted"}, {"spp", 64}, {"max_depth", 4}};
    Json overrides{{"spp", 16}, {"seed", 7}};
    EXPECT_EQ(mergeSettings(defaults, overrides), (Json{{"preset", "none"},
                                                        {"integrator", "whitted"},
                                                        {"spp", 16},
                                                        {"max_depth", 4},
                                                        {"seed", 7}}));
    EXPECT_EQ(mergeSettings(defaults, Json::object()), defaults);
    Json none = overrides;
    none["preset"] = "none";
    EXPECT_EQ(mergeSettings(Json::object(), none), none);
    // A non-object on either side contributes nothing.
    EXPECT_EQ(mergeSettings(defaults, Json()), defaults);
    EXPECT_EQ(mergeSettings(Json(), none), none);
    // A merged value is still validated.
    EXPECT_SETTINGS_ERROR(mergeSettings(defaults, Json{{"spp", 0}}), "/settings/spp",
                          "must be in [1, 1000000], got 0");
}

// Where neither side names a preset, auto is as if the scene named it: beneath the scene's values
// and the request's. Without the scene's traits it sets the sampler and pass size alone; its pass
// size shrinks to leave the spp asked 8 passes.
TEST(SettingsMerge, AutoIsTheDefaultPreset) {
    const Json defaults{{"integrator", "whitted"}, {"spp", 64}, {"sampler", "independent"}};
    EXPECT_EQ(mergeSettings(defaults, Json{{"seed", 7}}), (Json{{"preset", "auto"},
                                                                {"integrator", "whitted"},
                                                                {"spp", 64},
                                                                {"sampler", "independent"},
                                                                {"spp_per_pass", 8},
                                                                {"seed", 7}}));
    const RenderSettings s = parseSettings(mergeSettings(Json::object(), Json{{"spp", 256}}));
    EXPECT_EQ(s.preset, "auto");
    EXPECT_EQ(s.sampler, SamplerKind::SobolSequence);
    EXPECT_EQ(s.sppPerPass, presetSettings("auto")["spp_per_pass"].get<int>());
    EXPECT_EQ(RenderSettings{}.preset, "auto");
}

// A preset replaces the scene's values for what it sets; what the request names replaces the
// preset's; a scene may name a preset too, below its own values.
TEST(SettingsPresets, SitBetweenTheSceneAndTheRequest) {
    const Json scene{{"spp", 64}, {"max_depth", 4}, {"target_error", 0.5}};
    const Json preview = presetSettings("preview");
    ASSERT_TRUE(preview.contains("spp"));
    RenderSettings s = parseSettings(mergeSettings(scene, Json{{"preset", "preview"}}));
    EXPECT_EQ(s.preset, "preview");
    EXPECT_EQ(s.spp, preview["spp"].get<int>());
    EXPECT_EQ(s.targetError, preview["target_error"].get<double>());
    EXPECT_EQ(s.maxDepth, 4);  // the preview preset leaves it to the scene
    s = parseSettings(mergeSettings(scene, Json{{"preset", "preview"}, {"spp", 4}}));
    EXPECT_EQ(s.spp, 4);
    EXPECT_EQ(s.sppPerPass, 1);  // the preset's 8 per pass, cut to leave 8 passes (at least 1)
    s = parseSettings(mergeSettings(scene, Json{{"preset", "preview"}, {"spp", 160}}));
    EXPECT_EQ(s.sppPerPass, preview["spp_per_pass"].get<int>());
    // A scene's own preset is under its own values.
    s = parseSettings(mergeSettings(Json{{"preset", "final"}, {"spp", 64}}, Json::object()));
    EXPECT_EQ(s.spp, 64);
    EXPECT_EQ(s.targetError, presetSettings("final")["target_error"].get<double>());
    // none, and a request's preset over the scene's.
    s = parseSettings(mergeSettings(Json{{"preset", "final"}}, Json{{"preset", "none"}}));
    EXPECT_EQ(s.spp, RenderSettings{}.spp);
    s = parseSettings(mergeSettings(Json{{"preset", "final"}}, Json{{"preset", "draft"}}));
    EXPECT_EQ(s.spp, presetSettings("draft")["spp"].get<int>());
    // An unknown preset is an error at its path, naming the valid ones.
    EXPECT_SETTINGS_ERROR(mergeSettings(scene, Json{{"preset", "ultra"}}), "/settings/preset",
                          "unknown value \"ultra\"; valid: none, auto, draft, preview, final");
    EXPECT_SETTINGS_ERROR(mergeSettings(scene, Json{{"preset", 3}}), "/settings/preset",
                          "expected a string, got a number");
}

TEST(SettingsPresets, EveryPresetIsValidAndDocumented) {
    const Json schema = settingsSchemaJson();
    for (const Preset& p : presets()) {
        SCOPED_TRACE(p.name);
        EXPECT_NO_THROW(parseSettings(p.settings));
        EXPECT_EQ(schema["preset"]["presets"][p.name]["settings"], p.settings);
        EXPECT_FALSE(p.description.empty());
    }
    EXPECT_EQ(schema["preset"]["default"], "auto");
}

TEST(SettingsCommandLine, ParseSettingValue) {
    Json n = parseSettingValue("16");
    EXPECT_TRUE(n.is_number_integer());
    EXPECT_EQ(n, 16);
    EXPECT_TRUE(parseSettingValue("0.25").is_number_float());
    Json s = parseSettingValue("whitted");
    EXPECT_TRUE(s.is_string());
    EXPECT_EQ(s, "whitted");
    Json b = parseSettingValue("true");
    EXPECT_TRUE(b.is_boolean());
    EXPECT_EQ(b, true);
    EXPECT_EQ(parseSettingValue("\"16\""), "16");
    EXPECT_EQ(parseSettingValue(""), "");
    EXPECT_EQ(parseSettingValue("1.5.2"), "1.5.2");
    EXPECT_EQ(parseSettings(Json{{"spp", parseSettingValue("64")}}).spp, 64);
}

// Settings of spp samples per pixel in passes of sppPerPass (0: chosen).
RenderSettings sppSettings(int spp, int sppPerPass = 0) {
    RenderSettings s;
    s.spp = spp;
    s.sppPerPass = sppPerPass;
    return s;
}

TEST(SettingsPasses, ResolvedSppPerPass) {
    auto resolved = [](int spp, int sppPerPass = 0) {
        return sppSettings(spp, sppPerPass).resolvedSppPerPass();
    };
    EXPECT_EQ(resolved(64), 1);
    EXPECT_EQ(resolved(1024), 16);
    EXPECT_EQ(resolved(100), 1);
    EXPECT_EQ(resolved(97), 1);
    EXPECT_EQ(resolved(1), 1);
    EXPECT_EQ(resolved(16), 1);
    EXPECT_EQ(resolved(6400), 100);
    EXPECT_EQ(resolved(1000), 10);  // 1000 / 64 = 15; the largest divisor up to 15 is 10
    EXPECT_EQ(resolved(1024, 8), 8);
    EXPECT_EQ(resolved(100, 7), 7);
    for (int spp = 1; spp <= 5000; ++spp) {
        int perPass = resolved(spp);
        ASSERT_EQ(spp % perPass, 0) << spp;
        ASSERT_LE(perPass, std::max(1, spp / 64)) << spp;
    }
}

TEST(SettingsPasses, PassesTotalRoundsUp) {
    auto passes = [](int spp, int sppPerPass = 0) {
        return sppSettings(spp, sppPerPass).passesTotal();
    };
    EXPECT_EQ(passes(64), 64);
    EXPECT_EQ(passes(1024), 64);
    EXPECT_EQ(passes(1000), 100);
    EXPECT_EQ(passes(100, 7), 15);  // 14 passes of 7 take 98: a 15th takes the last 2 and 5 more
    EXPECT_EQ(passes(1024, 8), 128);
    EXPECT_EQ(passes(1), 1);
}

}  // namespace
}  // namespace caustic
