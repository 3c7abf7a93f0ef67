#include "render/settings.h"

#include <algorithm>
#include <cmath>

#include <unistd.h>

#include "accel/accelerator.h"
#include "core/error.h"
#include "integrators/integrator.h"
#include "scene/json_reader.h"

namespace caustic {

const std::vector<SettingSpec>& settingSpecs() {
    static const std::vector<SettingSpec> specs = [] {
        using T = SettingType;
        RenderSettings d;
        return std::vector<SettingSpec>{
            {"integrator",
             T::String,
             d.integrator,
             0,
             0,
             integratorNames(),
             "",
             "Light transport algorithm.",
             {}},
            {"spp",
             T::Integer,
             d.spp,
             1,
             1e6,
             {},
             "samples/pixel",
             "Samples per pixel; the render stops when it has taken them all.",
             {}},
            {"spp_per_pass",
             T::Integer,
             d.sppPerPass,
             0,
             1e6,
             {},
             "samples/pixel",
             "Samples per pixel in each pass (one independent estimate of the image). 0 chooses "
             "about 64 equal passes. Error estimates need at least 2 passes.",
             {}},
            {"time_limit",
             T::Number,
             d.timeLimit,
             0,
             1e6,
             {},
             "s",
             "Stop after the pass that reaches this wall time; 0 for no limit.",
             {}},
            {"target_error",
             T::Number,
             d.targetError,
             0,
             1,
             {},
             "",
             "Stop once the estimated relative RMS error is at most this; 0 for no target.",
             {}},
            {"max_depth",
             T::Integer,
             d.maxDepth,
             1,
             1e6,
             {},
             "bounces",
             "Most scattering events on a path (1: direct light only); for whitted, the depth of "
             "specular recursion.",
             {}},
            {"rr_depth",
             T::Integer,
             d.rrDepth,
             1,
             1e6,
             {},
             "bounces",
             "Bounces before Russian roulette may end a path (it continues with probability equal "
             "to its throughput, so the estimate stays unbiased).",
             {"path"}},
            {"light_sampling",
             T::Boolean,
             d.lightSampling,
             0,
             0,
             {},
             "",
             "Sample a light (chosen by power) at every non-specular vertex. Off: the naive path "
             "tracer, which finds emitters only by BSDF sampling and never sees point lights.",
             {"path"}},
            {"mis",
             T::Boolean,
             d.mis,
             0,
             0,
             {},
             "",
             "Weight light and BSDF samples by the power heuristic. Off (with light_sampling on): "
             "direct light at non-specular vertices comes from light samples only.",
             {"path"}},
            {"photons",
             T::Integer,
             d.photons,
             1,
             1e9,
             {},
             "photon paths/pass",
             "Photon paths traced from the lights in each pass (each stored photon takes 56 "
             "bytes).",
             {"photon", "ppm"}},
            {"caustic_photons",
             T::Integer,
             d.causticPhotons,
             0,
             1e9,
             {},
             "photon paths/pass",
             "Photon paths traced for the caustic map alone in each pass; each ends at its first "
             "diffuse hit, so they are cheap. 0 takes the caustic photons of the `photons` paths.",
             {"photon", "ppm"}},
            {"photon_lookup",
             T::String,
             d.photonLookup,
             0,
             0,
             {"kdtree", "brute_force"},
             "",
             "Photon search structure: the kd-tree, or every photon for every look-up (a baseline "
             "for benchmarks; the image is the same).",
             {"photon", "ppm"}},
            {"k",
             T::Integer,
             d.k,
             1,
             10000,
             {},
             "photons",
             "Photons per density estimate (the k nearest), when radius is 0.",
             {"photon"}},
            {"radius",
             T::Number,
             d.radius,
             0,
             1e30,
             {},
             "scene units",
             "photon: fixed density-estimation radius, 0 for the k nearest photons instead; ppm: "
             "the "
             "first pass's radius, 0 for 1/500 of the scene's diagonal.",
             {"photon", "ppm"}},
            {"kernel",
             T::String,
             d.kernel,
             0,
             0,
             {"box", "cone", "simpson"},
             "",
             "Density-estimation kernel: box (uniform), cone (1 - d/r) or simpson ((1 - "
             "d^2/r^2)^2), "
             "each normalized over its disk.",
             {"photon", "ppm"}},
            {"final_gather",
             T::Integer,
             d.finalGather,
             0,
             4096,
             {},
             "rays",
             "Final-gather rays per camera path for indirect light; 0 reads the global photon map "
             "at the visible point.",
             {"photon"}},
            {"alpha",
             T::Number,
             d.alpha,
             0.01,
             1,
             {},
             "",
             "Progressive photon mapping: pass i's squared radius is the previous one times "
             "(i - 1 + alpha) / i (Knaus & Zwicker 2011); smaller alpha shrinks it faster.",
             {"ppm"}},
            {"accelerator",
             T::String,
             d.accelerator,
             0,
             0,
             acceleratorNames(),
             "",
             "Ray intersection structure.",
             {}},
            {"memory_limit",
             T::Number,
             d.memoryLimit,
             0,
             1e9,
             {},
             "MiB",
             "Refuse, before the first pass, a render whose estimated peak memory (scene, "
             "accelerator, film, photon maps) exceeds this; 0 for half the machine's memory.",
             {}},
            {"seed",
             T::Integer,
             d.seed,
             0,
             9007199254740991.0,
             {},
             "",
             "Random seed: the same scene, settings and seed give the same image.",
             {}},
            {"threads",
             T::Integer,
             d.threads,
             0,
             1024,
             {},
             "",
             "Worker threads; 0 uses every core. The image does not depend on it.",
             {}},
            {"exposure",
             T::Number,
             d.exposure,
             -20,
             20,
             {},
             "stops",
             "Scales PNG output by 2^exposure before sRGB encoding; EXR output stays linear.",
             {}},
        };
    }();
    return specs;
}

Json settingsSchemaJson() {
    static const char* typeNames[] = {"integer", "number", "boolean", "string"};
    Json out = Json::object();
    for (const SettingSpec& s : settingSpecs()) {
        Json j{{"type", typeNames[static_cast<int>(s.type)]},
               {"default", s.defaultValue},
               {"description", s.description}};
        if (s.type == SettingType::Integer || s.type == SettingType::Number) {
            j["minimum"] = s.min;
            j["maximum"] = s.max;
        }
        if (!s.choices.empty()) j["enum"] = s.choices;
        if (!s.unit.empty()) j["unit"] = s.unit;
        j["integrators"] = s.integrators;
        out[s.name] = j;
    }
    return out;
}

Json mergeSettings(const Json& defaults, const Json& overrides) {
    Json merged = defaults.is_object() ? defaults : Json::object();
    if (overrides.is_object())
        for (auto it = overrides.begin(); it != overrides.end(); ++it)
            merged[it.key()] = it.value();
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
    Json values = Json::object();
    for (const SettingSpec& spec : settingSpecs()) values[spec.name] = spec.defaultValue;
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
        values[it.key()] = validate(*spec, it.value(), at);
    }
    RenderSettings r;
    r.integrator = values["integrator"].get<std::string>();
    r.spp = values["spp"].get<int>();
    r.sppPerPass = values["spp_per_pass"].get<int>();
    r.timeLimit = values["time_limit"].get<double>();
    r.targetError = values["target_error"].get<double>();
    r.maxDepth = values["max_depth"].get<int>();
    r.rrDepth = values["rr_depth"].get<int>();
    r.lightSampling = values["light_sampling"].get<bool>();
    r.mis = values["mis"].get<bool>();
    r.photons = values["photons"].get<int64_t>();
    r.causticPhotons = values["caustic_photons"].get<int64_t>();
    r.photonLookup = values["photon_lookup"].get<std::string>();
    r.k = values["k"].get<int>();
    r.radius = values["radius"].get<double>();
    r.kernel = values["kernel"].get<std::string>();
    r.finalGather = values["final_gather"].get<int>();
    r.alpha = values["alpha"].get<double>();
    r.accelerator = values["accelerator"].get<std::string>();
    r.memoryLimit = values["memory_limit"].get<double>();
    r.seed = values["seed"].get<uint64_t>();
    r.threads = values["threads"].get<int>();
    r.exposure = values["exposure"].get<double>();
    if (r.sppPerPass > r.spp)
        throw InputError(jsonPointer(path, "spp_per_pass"),
                         "must be at most spp (" + std::to_string(r.spp) + ")");
    return r;
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
    return Json{{"integrator", integrator},
                {"spp", spp},
                {"spp_per_pass", sppPerPass},
                {"time_limit", timeLimit},
                {"target_error", targetError},
                {"max_depth", maxDepth},
                {"rr_depth", rrDepth},
                {"light_sampling", lightSampling},
                {"mis", mis},
                {"photons", photons},
                {"caustic_photons", causticPhotons},
                {"photon_lookup", photonLookup},
                {"k", k},
                {"radius", radius},
                {"kernel", kernel},
                {"final_gather", finalGather},
                {"alpha", alpha},
                {"accelerator", accelerator},
                {"memory_limit", memoryLimit},
                {"seed", seed},
                {"threads", threads},
                {"exposure", exposure}};
}

Json parseSettingValue(const std::string& text) {
    // Text nested deeper than a scene may be stays a string, which no setting takes: merging the
    // settings copies values recursively, and 40000 levels (an argument holds 65000) overflowed
    // the stack of a sanitizer build (issue 12, bug 3).
    std::optional<Json> v = tryParseJson(text);
    return v ? std::move(*v) : Json(text);
}

}  // namespace caustic
