#include "render/presets.h"

#include <algorithm>

#include "render/scene_traits.h"

namespace caustic {

// From the study (bench_study, docs/study/README.md: 96x96, every example scene, path tracing).
// Preview's adaptive sampling reached each scene's target RMSE 1.43 to 3.27 times sooner than path
// with independent numbers: the fastest of all on the bunny (photon maps, or sobol at 16 a pass,
// win on the others). But adaptive sampling starves dark pixels (uniform sampling's relative MSE
// is 0.63 to 0.93 times its), so final, whose dark corners matter, samples uniformly; draft stops
// before the pilot ends. The error target stops each as soon as it is met, spp being a ceiling.
// Each takes the photon maps the scene needs (photonMapsFor): with both maps the study's scenes
// reached path's error 2.1 to 4.1 times sooner at equal time than path alone, 1.2 to 2.4 times
// sooner than with the preset's sampler alone (docs/study/README.md, sobol at equal time).
//
// Pass sizes: a render with a photon map stops on its target no sooner than its 8th pass
// (render/stopping.h), so 16 a pass would render at least 128 spp where the maps reach 2% at
// 32; but every pass traces its photons anew, so passes of 4 cost more where a tight target
// needs hundreds of spp. Measured at 128x128, 2 seeds (bench/preset_stops.sh --per-pass): at 3%
// passes of 4 stopped 1.2 to 1.5 times sooner than passes of 8; at 1%, passes of 8 were within
// 1.14 to 1.96 times the fastest of 4, 8 and 16 on the bunny, cornell-box and cornell-spheres,
// where 4 was 1.86 times slower on cornell-spheres (36 passes) and 16 up to 3.4 times on the
// bunny. Auto follows the same rule for the target it is given (Preset::underTarget).
//
// All run one Sobol' sequence through a pixel's passes (sobol_sequence). Each pass is then
// the same net as with sobol, so the passes' spread, and with it the reported error and the pass
// at which the target stops a render, are about the same; but the passes fill each other's gaps,
// so the image is truer than that spread says. Measured at 128x128, 2 seeds, against 4096-spp
// references (bench/preset_stops.sh, with the maps): the true error at the stop is 10% to 32%
// lower than with sobol at the same pass; the reported error is then 1.22 to 1.43 times the true
// one (sobol's 0.92 to 1.04), an estimate on the safe side.
const std::vector<Preset>& presets() {
    static const std::vector<Preset> table = {
        {"auto",
         "How to render, from what the scene holds: photon maps where it needs them (a caustic map "
         "for mirrors and glass under local lights, an indirect map for diffuse interreflection), "
         "one Sobol' sequence through 16 samples a pass; under a target error, 4 a pass for "
         "targets of 2% or more and 8 for 1% or more. Sets no spp or target: the scene's and "
         "the request's hold. The job says what it chose and why (preset_choice).",
         {{"sampler", "sobol_sequence"}, {"spp_per_pass", 16}},
         true,
         {{{"target_error", 0.02}, {"settings", {{"spp_per_pass", 4}}}},
          {{"target_error", 0.01}, {"settings", {{"spp_per_pass", 8}}}}}},
        {"draft",
         "A quick look: at most 16 spp, stopping at 10% relative error.",
         {{"spp", 16}, {"spp_per_pass", 4}, {"sampler", "sobol_sequence"}, {"target_error", 0.1}},
         true},
        {"preview",
         "Good enough to judge light and materials: adaptive sampling, at most 256 spp, stopping "
         "at 3%.",
         {{"spp", 256},
          {"spp_per_pass", 4},
          {"sampler", "sobol_sequence"},
          {"adaptive", true},
          {"target_error", 0.03}},
         true},
        {"final",
         "For the record: uniform sampling, at most 8192 spp, stopping at 1% relative error.",
         {{"spp", 8192},
          {"spp_per_pass", 8},
          {"sampler", "sobol_sequence"},
          {"adaptive", false},
          {"target_error", 0.01}},
         true},
    };
    return table;
}

nlohmann::json photonMapsFor(const SceneTraits& t) {
    nlohmann::json settings = nlohmann::json::object(), reasons = nlohmann::json::array();
    // One map: taken when the scene has its surfaces (`has`) under local lights.
    auto choose = [&](const std::string& key, bool has, const std::string& without,
                      const std::string& why) {
        if (has && t.localLight()) settings[key] = "photon_map";
        reasons.push_back(key + ": " +
                          (!has             ? "path tracing; " + without
                           : t.localLight() ? "photon_map; " + why
                                            : "path tracing; most of the light comes from "
                                              "infinitely far (environment, sun): photons would "
                                              "spread over the whole scene's extent, few where "
                                              "the camera looks"));
    };
    choose("caustics", t.specular, "no mirror or smooth glass makes caustics",
           "mirrors or smooth glass under local lights make caustics, which paths from the "
           "camera find only by chance");
    choose("indirect", t.diffuse, "no diffuse surface to interreflect",
           "diffuse surfaces under local lights: their interreflection from an indirect photon "
           "map at the second diffuse bounce");
    return {{"settings", settings}, {"reasons", reasons}};
}

namespace {

const Preset* findPreset(const nlohmann::json& name) {
    if (name.is_string())
        for (const Preset& p : presets())
            if (p.name == name.get<std::string>()) return &p;
    return nullptr;
}

// The preset's settings for a render of target error `target` (Preset::underTarget); null for
// none (no target, or one tighter than every bound).
const nlohmann::json* underTargetFor(const Preset& p, double target) {
    if (target > 0)
        for (const nlohmann::json& rung : p.underTarget)
            if (target >= rung["target_error"].get<double>()) return &rung["settings"];
    return nullptr;
}

}  // namespace

nlohmann::json presetSettings(const nlohmann::json& name, const SceneTraits* traits,
                              double targetError) {
    const Preset* p = findPreset(name);
    if (!p) return nlohmann::json::object();
    nlohmann::json settings = p->settings;
    if (const nlohmann::json* under = underTargetFor(*p, targetError)) settings.update(*under);
    if (p->sceneMaps && traits) settings.update(photonMapsFor(*traits)["settings"]);
    return settings;
}

nlohmann::json presetPassSize(const nlohmann::json& perPass, const nlohmann::json& spp) {
    if (!perPass.is_number_integer() || !spp.is_number_integer() ||
        spp.get<int64_t>() >= 8 * perPass.get<int64_t>())
        return perPass;
    return std::max<int64_t>(1, spp.get<int64_t>() / 8);
}

nlohmann::json presetChoice(const nlohmann::json& merged, const SceneTraits& traits) {
    const Preset* p = findPreset(merged.value("preset", nlohmann::json()));
    if (!p || !p->sceneMaps) return nullptr;
    nlohmann::json choice = photonMapsFor(traits), settings = nlohmann::json::object();
    for (auto& [key, value] : choice["settings"].items()) {
        if (merged.value(key, nlohmann::json()) == value) {
            settings[key] = value;
            continue;
        }
        for (nlohmann::json& reason : choice["reasons"])
            if (reason.get<std::string>().starts_with(key + ":"))
                reason = reason.get<std::string>() + " (replaced by " + key + "=" +
                         merged.value(key, nlohmann::json()).dump() +
                         " from the scene or the request)";
    }
    choice["settings"] = settings;
    choice["preset"] = p->name;
    // The pass size it took, where that depends on the target; the settings it reports are the
    // maps alone, which a service's limits may replace by paths (server/jobs/submission.cpp).
    if (!p->underTarget.empty()) {
        // Read before the settings are validated (server/jobs/submission.cpp): a target that is
        // no number is none here, and parseSettings refuses it at its path.
        const nlohmann::json& given =
            merged.contains("target_error") ? merged["target_error"] : nlohmann::json();
        const double target = given.is_number() ? given.get<double>() : 0.0;
        const nlohmann::json* under = underTargetFor(*p, target);
        const nlohmann::json size =
            presetPassSize((under ? *under : p->settings).value("spp_per_pass", nlohmann::json()),
                           merged.value("spp", nlohmann::json()));
        if (merged.value("spp_per_pass", nlohmann::json()) == size)
            choice["reasons"].push_back(
                "spp_per_pass: " + size.dump() +
                (target <= 0 ? "; no target error: fewer, larger passes, each costing less to "
                               "merge and, with a photon map, to trace photons for"
                             : "; a target error of " + nlohmann::json(target).dump() +
                                   ": passes small enough to stop near the one that reaches "
                                   "it, large enough that their photons cost little"));
    }
    return choice;
}

}  // namespace caustic
