// The settings table: every row's default and type, the field each row is bound to, the settings
// each integrator's JSON lists, and JSON round trips through parseSettings.
#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "accel/accelerator.h"
#include "integrators/integrator.h"
#include "render/integrator_factory.h"
#include "render/settings.h"

namespace caustic {
namespace {

const SettingSpec& spec(const std::string& name) {
    for (const SettingSpec& s : settingSpecs())
        if (s.name == name) return s;
    throw std::out_of_range(name);
}

// The names of the settings integrator `name` reads.
// What `name` reads; for path, the photon settings only with its photon maps.
std::set<std::string> readBy(const std::string& name, bool photonMaps = false) {
    std::set<std::string> names;
    for (const SettingSpec& s : settingSpecs())
        if (s.readBy(name) && !(name == "path" && s.pathMaps != 0 && !photonMaps))
            names.insert(s.name);
    return names;
}

std::set<std::string> keys(const Json& j) {
    std::set<std::string> names;
    for (auto it = j.begin(); it != j.end(); ++it) names.insert(it.key());
    return names;
}

// A valid value of `s` other than its default, from the row alone, so that a new row is covered.
Json otherValue(const SettingSpec& s) {
    switch (s.type) {
        case SettingType::Boolean:
            return !s.defaultValue.get<bool>();
        case SettingType::String:
            for (const std::string& c : s.choices)
                if (c != s.defaultValue) return c;
            break;
        case SettingType::Integer: {
            int64_t d = s.defaultValue.get<int64_t>();
            return double(d + 1) <= s.max ? d + 1 : d - 1;
        }
        case SettingType::Number: {
            double d = s.defaultValue.get<double>();
            return d < s.max ? d + 0.25 * (s.max - d) : d - 0.25 * (d - s.min);
        }
    }
    ADD_FAILURE() << s.name << " has a single valid value";
    return s.defaultValue;
}

// Every setting at a value other than its default, for integrator `name`.
Json nonDefaultJson(const std::string& name) {
    Json j = Json::object();
    for (const SettingSpec& s : settingSpecs()) j[s.name] = otherValue(s);
    j["integrator"] = name;
    return j;
}

TEST(SettingsTable, EveryDefaultIsOfItsTypeAndInItsRange) {
    for (const SettingSpec& s : settingSpecs()) {
        SCOPED_TRACE(s.name);
        EXPECT_FALSE(s.description.empty());
        EXPECT_EQ(s.type, s.field.type);
        const Json& d = s.defaultValue;
        switch (s.type) {
            case SettingType::Integer:
                ASSERT_TRUE(d.is_number_integer());
                EXPECT_TRUE(s.choices.empty());
                break;
            case SettingType::Number:
                ASSERT_TRUE(d.is_number());
                EXPECT_TRUE(s.choices.empty());
                break;
            case SettingType::Boolean:
                EXPECT_TRUE(d.is_boolean());
                break;
            case SettingType::String:
                ASSERT_TRUE(d.is_string());
                EXPECT_NE(std::find(s.choices.begin(), s.choices.end(), d), s.choices.end());
                break;
        }
        if (s.type == SettingType::Integer || s.type == SettingType::Number) {
            EXPECT_LE(s.min, s.max);
            EXPECT_LE(s.min, d.get<double>());
            EXPECT_GE(s.max, d.get<double>());
        }
        // What the table says it reads, integrators exist to read.
        for (const std::string& name : s.integrators)
            EXPECT_NE(std::find(integratorNames().begin(), integratorNames().end(), name),
                      integratorNames().end())
                << name;
    }
    Json schema = settingsSchemaJson();
    EXPECT_EQ(schema.size(), settingSpecs().size());
    EXPECT_EQ(schema["spp"]["type"], "integer");
    EXPECT_EQ(schema["spp"]["minimum"], 1.0);
    EXPECT_EQ(schema["spp"]["maximum"], 1e6);
    EXPECT_EQ(schema["integrator"]["enum"], Json(integratorNames()));
    EXPECT_EQ(schema["kernel"]["default"], "cone");
    EXPECT_EQ(schema["alpha"]["integrators"], Json::array({"path", "ppm"}));
}

TEST(SettingsTable, DefaultsAreTheFieldsOfADefaultRenderSettings) {
    RenderSettings s = parseSettings(Json::object());
    EXPECT_EQ(s.integrator, "path");
    EXPECT_EQ(s.spp, 16);
    EXPECT_EQ(s.sppPerPass, 0);
    EXPECT_EQ(s.timeLimit, 0.0);
    EXPECT_EQ(s.targetError, 0.0);
    EXPECT_EQ(s.maxDepth, 16);
    EXPECT_EQ(s.path.rrDepth, 3);
    EXPECT_TRUE(s.path.lightSampling && s.path.mis);
    EXPECT_EQ(s.photon.photons, 200000u);
    EXPECT_EQ(s.photon.lookup, PhotonLookup::KdTree);
    EXPECT_EQ(s.photon.kernel, PhotonKernel::Cone);
    EXPECT_EQ(s.photon.alpha, 2.0 / 3.0);
    EXPECT_EQ(s.accelerator, "embree");
    EXPECT_EQ(s.seed, 0u);
    EXPECT_EQ(s.threads, 0);
    EXPECT_EQ(s.exposure, 0.0);
    EXPECT_EQ(s.toJson(), RenderSettings().toJson());
    for (const std::string& name : integratorNames()) {
        SCOPED_TRACE(name);
        RenderSettings d;
        d.integrator = name;
        Json j = d.toJson();
        for (auto it = j.begin(); it != j.end(); ++it) {
            if (it.key() != "integrator") {
                EXPECT_EQ(it.value(), spec(it.key()).defaultValue);
            }
        }
    }
}

// Parsing writes each setting into the field its row names, and toJson reads it from there.
TEST(SettingsTable, EveryRowIsBoundToItsField) {
    const Json asked{{"preset", "preview"},
                     {"integrator", "ppm"},
                     {"spp", 100},
                     {"spp_per_pass", 10},
                     {"time_limit", 2.5},
                     {"target_error", 0.01},
                     {"max_depth", 5},
                     {"rr_depth", 7},
                     {"light_sampling", false},
                     {"mis", false},
                     {"caustics", "photon_map"},
                     {"indirect", "photon_map"},
                     {"indirect_photons", 4321},
                     {"indirect_radius", 0.125},
                     {"photons", 12345},
                     {"caustic_photons", 678},
                     {"photon_lookup", "brute_force"},
                     {"k", 9},
                     {"radius", 0.25},
                     {"kernel", "simpson"},
                     {"final_gather", 3},
                     {"follow_roughness", 0.25},
                     {"alpha", 0.5},
                     {"sampler", "sobol"},
                     {"adaptive", true},
                     {"emission_samples", 5},
                     {"accelerator", "bruteforce"},
                     {"memory_limit", 512.5},
                     {"seed", 12345678901},
                     {"threads", 11},
                     {"width", 320},
                     {"height", 200},
                     {"exposure", -1.5}};
    RenderSettings s = parseSettings(asked);
    EXPECT_EQ(s.integrator, "ppm");
    EXPECT_EQ(s.spp, 100);
    EXPECT_EQ(s.sppPerPass, 10);
    EXPECT_EQ(s.timeLimit, 2.5);
    EXPECT_EQ(s.targetError, 0.01);
    EXPECT_EQ(s.maxDepth, 5);
    EXPECT_EQ(s.path.rrDepth, 7);
    EXPECT_FALSE(s.path.lightSampling);
    EXPECT_FALSE(s.path.mis);
    EXPECT_EQ(s.path.caustics, PathSource::PhotonMap);
    EXPECT_EQ(s.path.indirect, PathSource::PhotonMap);
    EXPECT_EQ(s.path.indirectPhotons, 4321u);
    EXPECT_EQ(s.path.indirectRadius, 0.125);
    EXPECT_EQ(s.photon.photons, 12345u);
    EXPECT_EQ(s.photon.causticPhotons, 678u);
    EXPECT_EQ(s.photon.lookup, PhotonLookup::BruteForce);
    EXPECT_EQ(s.photon.k, 9);
    EXPECT_EQ(s.photon.radius, 0.25);
    EXPECT_EQ(s.photon.kernel, PhotonKernel::Simpson);
    EXPECT_EQ(s.photon.finalGather, 3);
    EXPECT_EQ(s.photon.followRoughness, 0.25);
    EXPECT_EQ(s.photon.alpha, 0.5);
    EXPECT_EQ(s.sampler, SamplerKind::Sobol);
    EXPECT_TRUE(s.adaptive);
    EXPECT_EQ(s.emissionSamples, 5);
    EXPECT_EQ(s.preset, "preview");
    EXPECT_EQ(s.accelerator, "bruteforce");
    EXPECT_EQ(s.memoryLimit, 512.5);
    EXPECT_EQ(s.seed, 12345678901u);
    EXPECT_EQ(s.threads, 11);
    EXPECT_EQ(s.width, 320);
    EXPECT_EQ(s.height, 200);
    EXPECT_EQ(s.exposure, -1.5);
    EXPECT_EQ(parseSettings(Json{{"kernel", "box"}}).photon.kernel, PhotonKernel::Box);
    // Read back, for the integrators that list them.
    for (const char* name : {"ppm", "path"}) {
        s.integrator = name;
        Json expected = asked;
        expected["integrator"] = name;
        for (const SettingSpec& row : settingSpecs())
            if (!s.reads(row)) expected.erase(row.name);
        EXPECT_EQ(s.toJson(), expected) << name;
    }
    // light_sampling and mis apart (both off above).
    RenderSettings lightOnly = parseSettings(Json{{"light_sampling", true}, {"mis", false}});
    EXPECT_TRUE(lightOnly.path.lightSampling);
    EXPECT_FALSE(lightOnly.path.mis);
    EXPECT_EQ(lightOnly.toJson()["mis"], false);
    EXPECT_EQ(lightOnly.toJson()["light_sampling"], true);
}

TEST(SettingsJson, EachIntegratorListsTheGeneralSettingsAndWhatItReads) {
    std::set<std::string> listed;
    for (const std::string& name : integratorNames()) {
        SCOPED_TRACE(name);
        RenderSettings s;
        s.integrator = name;
        EXPECT_EQ(keys(s.toJson()), readBy(name));
        listed.merge(keys(s.toJson()));
    }
    // Path's indirect map's own settings, listed only beside it.
    RenderSettings mapped;
    mapped.path.indirect = PathSource::PhotonMap;
    listed.merge(keys(mapped.toJson()));
    EXPECT_EQ(listed.size(), settingSpecs().size()) << "a setting no integrator lists";
}

TEST(SettingsJson, APathJobListsNoPhotonSetting) {
    Json asked = nonDefaultJson("path");
    asked["caustics"] = "paths";
    asked["indirect"] = "paths";
    Json j = parseSettings(asked).toJson();
    for (const char* name : {"photons", "caustic_photons", "photon_lookup", "k", "radius", "kernel",
                             "final_gather", "alpha", "indirect_photons", "indirect_radius"})
        EXPECT_FALSE(j.contains(name)) << name;
    for (const char* name : {"integrator", "spp", "max_depth", "rr_depth", "light_sampling", "mis",
                             "accelerator", "seed", "threads", "exposure"})
        EXPECT_TRUE(j.contains(name)) << name;
    // Unless its caustics come from a photon map: then it lists that map's settings.
    RenderSettings mapped = parseSettings(Json{{"caustics", "photon_map"}, {"photons", 1000}});
    Json m = mapped.toJson();
    for (const char* name : {"photons", "photon_lookup", "radius", "kernel", "alpha"})
        EXPECT_TRUE(m.contains(name)) << name;
    for (const char* name :
         {"caustic_photons", "k", "final_gather", "indirect_photons", "indirect_radius"})
        EXPECT_FALSE(m.contains(name)) << name;
    EXPECT_EQ(m["photons"], 1000);
    EXPECT_EQ(parseSettings(m).toJson(), m);
    // Or its indirect light: then that map's settings, and those both maps read.
    Json i = parseSettings(Json{{"indirect", "photon_map"}, {"indirect_photons", 2000}}).toJson();
    for (const char* name :
         {"indirect_photons", "indirect_radius", "photon_lookup", "kernel", "alpha"})
        EXPECT_TRUE(i.contains(name)) << name;
    for (const char* name : {"photons", "radius", "caustic_photons", "k", "final_gather"})
        EXPECT_FALSE(i.contains(name)) << name;
    EXPECT_EQ(i["indirect_photons"], 2000);
    EXPECT_EQ(parseSettings(i).toJson(), i);
    // Nor does a ray caster list the path length it never follows.
    RenderSettings raycast;
    raycast.integrator = "raycast";
    EXPECT_FALSE(raycast.toJson().contains("max_depth"));
}

TEST(SettingsJson, EveryIntegratorRoundTrips) {
    for (const std::string& name : integratorNames()) {
        SCOPED_TRACE(name);
        const Json asked = nonDefaultJson(name);
        Json j = parseSettings(asked).toJson();
        ASSERT_EQ(keys(j), readBy(name, /*photonMaps=*/true));  // caustics, indirect: photon_map
        for (auto it = j.begin(); it != j.end(); ++it) {
            EXPECT_EQ(it.value(), asked[it.key()]) << it.key();
            if (it.key() != "integrator") {
                EXPECT_NE(it.value(), spec(it.key()).defaultValue);
            }
        }
        EXPECT_EQ(parseSettings(j).toJson(), j);
        // And through JSON text.
        EXPECT_EQ(parseSettings(Json::parse(j.dump())).toJson(), j);
    }
}

TEST(SettingsJson, EveryKeyAloneKeepsTheOthersAtTheirDefaults) {
    for (const SettingSpec& s : settingSpecs()) {
        SCOPED_TRACE(s.name);
        // The first integrator that reads it alone (path reads a photon setting only beside
        // caustics = photon_map); path alone reads its indirect map's, beside indirect =
        // photon_map.
        const std::string integrator = s.name == "integrator"  ? otherValue(s).get<std::string>()
                                       : s.integrators.empty() ? "path"
                                       : s.pathMaps != 0       ? s.integrators.back()
                                                               : s.integrators.front();
        const bool indirectMap = integrator == "path" && s.pathMaps != 0;
        Json one{{"integrator", integrator}, {s.name, otherValue(s)}};
        // The defaults with this one field changed (which may list more settings: caustics).
        RenderSettings changed;
        changed.integrator = integrator;
        if (indirectMap) {
            one["indirect"] = "photon_map";
            changed.path.indirect = PathSource::PhotonMap;
        }
        s.field.set(changed, otherValue(s), s.choices);
        const Json j = parseSettings(one).toJson();
        EXPECT_EQ(j, changed.toJson());
        EXPECT_EQ(j[s.name], otherValue(s));
    }
}

// A scene's settings may serve several integrators, and job records written before the JSON
// output listed only the integrator's settings hold every one: both still parse.
TEST(SettingsJson, EverySettingIsAcceptedWhateverTheIntegrator) {
    for (const std::string& name : integratorNames()) {
        SCOPED_TRACE(name);
        RenderSettings s = parseSettings(nonDefaultJson(name));
        EXPECT_EQ(s.photon.photons, otherValue(spec("photons")).get<uint64_t>());
        EXPECT_EQ(s.path.rrDepth, otherValue(spec("rr_depth")).get<int>());
        EXPECT_EQ(s.maxDepth, otherValue(spec("max_depth")).get<int>());
    }
}

}  // namespace
}  // namespace caustic
