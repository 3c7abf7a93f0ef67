#include "render/settings.h"

#include <algorithm>
#include <cmath>

#include <unistd.h>

#include "core/error.h"
#include "render/integrator_factory.h"
#include "render/presets.h"
#include "scene/json_reader.h"

namespace caustic {

const char* toString(SettingType type) {
    static const char* names[] = {"integer", "number", "boolean", "string"};
    return names[static_cast<int>(type)];
}

Json settingsSchemaJson() {
    Json out = Json::object();
    for (const SettingSpec& s : settingSpecs()) {
        Json j{{"type", toString(s.type)},
               {"default", s.defaultValue},
               {"description", s.description}};
        if (s.type == SettingType::Integer || s.type == SettingType::Number) {
            j["minimum"] = s.min;
            j["maximum"] = s.max;
        }
        if (!s.choices.empty()) j["enum"] = s.choices;
        if (!s.unit.empty()) j["unit"] = s.unit;
        j["integrators"] = s.integrators;
        // Read by path only beside one of its photon maps (RenderSettings::reads).
        if (s.pathMaps != 0) {
            Json alternatives = Json::array();
            if (s.pathMaps & SettingSpec::kCausticMap)
                alternatives.push_back({{"caustics", "photon_map"}});
            if (s.pathMaps & SettingSpec::kIndirectMap)
                alternatives.push_back({{"indirect", "photon_map"}});
            j["only_with"] = {{"path", alternatives}};
        }
        if (s.name == "preset") {
            // What each preset sets, for the API's users and the page's preset menu.
            Json sets = Json::object();
            for (const Preset& p : presets())
                sets[p.name] = {{"description", p.description},
                                {"settings", p.settings},
                                {"under_target", p.underTarget},
                                {"scene_maps", p.sceneMaps}};
            j["presets"] = sets;
        }
        out[s.name] = j;
    }
    return out;
}

namespace {

void overlay(Json& onto, const Json& values) {
    if (values.is_object())
        for (auto it = values.begin(); it != values.end(); ++it) onto[it.key()] = it.value();
}

// The merge of mergeSettings, with the preset's settings for a render with or without a target.
Json mergeWithPreset(const Json& defaults, const Json& overrides, const SceneTraits* traits,
                     double targetError) {
    const bool overridden = overrides.is_object() && overrides.contains("preset");
    // Where neither names a preset, the default one (RenderSettings::preset) is as if the
    // defaults named it: beneath their values.
    const Json defaultPreset = RenderSettings().preset;
    const Json& named = overridden                                            ? overrides["preset"]
                        : defaults.is_object() && defaults.contains("preset") ? defaults["preset"]
                                                                              : defaultPreset;
    const Json preset = presetSettings(named, traits, targetError);
    Json merged = Json::object();
    if (!overridden) {
        merged["preset"] = named;
        overlay(merged, preset);
    }
    overlay(merged, defaults);
    if (overridden) overlay(merged, preset);
    overlay(merged, overrides);
    // A preset's passes must leave an spp given beside it (`--preset final --spp 64`) the 8
    // passes an error estimate needs, as far as it can.
    const Json& perPass = merged.contains("spp_per_pass") ? merged["spp_per_pass"] : Json();
    const bool presetSpp = preset.contains("spp") && merged.value("spp", Json()) == preset["spp"];
    if (preset.contains("spp_per_pass") && perPass == preset["spp_per_pass"] && !presetSpp)
        merged["spp_per_pass"] = presetPassSize(perPass, merged.value("spp", Json()));
    return merged;
}

}  // namespace

Json mergeSettings(const Json& defaults, const Json& overrides, const SceneTraits* traits) {
    const Json merged = mergeWithPreset(defaults, overrides, traits, 0);
    // A preset's settings under a target (Preset::underTarget) set no target themselves, so the
    // target of the first merge is the second's.
    const Json& target = merged.contains("target_error") ? merged["target_error"] : Json();
    if (target.is_number() && target.get<double>() > 0)
        return mergeWithPreset(defaults, overrides, traits, target.get<double>());
    return merged;
}

namespace {

std::string formatNumber(double v) {
    Json j = v;
    // Integral values print as integers up to 2^53 (the largest seed is 2^53 - 1).
    if (v == std::floor(v) && std::abs(v) <= 9007199254740992.0) j = static_cast<int64_t>(v);
    return j.dump();
}

// Validates one value against its spec; returns it normalized.
Json validate(const SettingSpec& spec, const Json& v, const std::string& path) {
    switch (spec.type) {
        case SettingType::Integer:
        case SettingType::Number: {
            double x = spec.type == SettingType::Integer ? static_cast<double>(readInteger(v, path))
                                                         : static_cast<double>(readNumber(v, path));
            if (spec.type == SettingType::Number) x = v.get<double>();
            if (x < spec.min || x > spec.max)
                throw InputError(path, "must be in [" + formatNumber(spec.min) + ", " +
                                           formatNumber(spec.max) + "], got " + formatNumber(x));
            return spec.type == SettingType::Integer ? Json(static_cast<int64_t>(x)) : Json(x);
        }
        case SettingType::Boolean:
            if (!v.is_boolean())
                throw InputError(path, "expected a boolean, got " + jsonTypeName(v));
            return v;
        case SettingType::String: {
            if (!v.is_string()) throw InputError(path, "expected a string, got " + jsonTypeName(v));
            std::string s = v.get<std::string>();
            if (!spec.choices.empty() &&
                std::find(spec.choices.begin(), spec.choices.end(), s) == spec.choices.end()) {
                std::string valid;
                for (const std::string& c : spec.choices) valid += (valid.empty() ? "" : ", ") + c;
                throw InputError(path, "unknown value \"" + s + "\"; valid: " + valid);
            }
            return v;
        }
    }
    return v;
}

}  // namespace

RenderSettings parseSettings(const Json& settings, const std::string& path) {
    if (!settings.is_object())
        throw InputError(path, "expected an object, got " + jsonTypeName(settings));
    RenderSettings r;
    for (auto it = settings.begin(); it != settings.end(); ++it) {
        auto spec = std::find_if(settingSpecs().begin(), settingSpecs().end(),
                                 [&](const SettingSpec& s) { return s.name == it.key(); });
        std::string at = jsonPointer(path, it.key());
        if (spec == settingSpecs().end()) {
            std::string valid;
            for (const SettingSpec& s : settingSpecs())
                valid += (valid.empty() ? "" : ", ") + s.name;
            throw InputError(at, "unknown setting; valid settings: " + valid);
        }
        spec->field.set(r, validate(*spec, it.value(), at), spec->choices);
    }
    if (r.sppPerPass > r.spp)
        throw InputError(jsonPointer(path, "spp_per_pass"),
                         "must be at most spp (" + std::to_string(r.spp) + ")");
    return r;
}

int RenderSettings::passesTotal() const {
    const int perPass = resolvedSppPerPass();
    return (spp + perPass - 1) / perPass;
}

int RenderSettings::resolvedSppPerPass() const {
    if (sppPerPass > 0) return sppPerPass;
    int best = 1;
    for (int d = 1; d <= spp / 64; ++d)
        if (spp % d == 0) best = d;
    return best;
}

size_t RenderSettings::memoryLimitBytes() const {
    if (memoryLimit > 0) return size_t(memoryLimit * 1048576.0);
    long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && pageSize > 0 ? size_t(pages) * size_t(pageSize) / 2 : size_t(4) << 30;
}

Json RenderSettings::toJson() const {
    Json out = Json::object();
    for (const SettingSpec& spec : settingSpecs())
        if (reads(spec)) out[spec.name] = spec.field.get(*this, spec.choices);
    return out;
}

bool RenderSettings::reads(const SettingSpec& spec) const {
    if (!spec.readBy(integrator)) return false;
    if (spec.pathMaps == 0) return true;
    const IntegratorTraits* traits = findIntegrator(integrator);
    if (!traits || !traits->photonMapsBySetting) return true;
    return ((spec.pathMaps & SettingSpec::kCausticMap) && path.caustics == PathSource::PhotonMap) ||
           ((spec.pathMaps & SettingSpec::kIndirectMap) && path.indirect == PathSource::PhotonMap);
}

Json parseSettingValue(const std::string& text) {
    // Text nested deeper than a scene may be stays a string, which no setting takes: merging the
    // settings copies values recursively, and tens of thousands of levels (an argument holds
    // 65000) overflow the stack of a sanitizer build.
    std::optional<Json> v = tryParseJson(text);
    return v ? std::move(*v) : Json(text);
}

}  // namespace caustic
