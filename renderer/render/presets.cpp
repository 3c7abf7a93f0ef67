#include "render/presets.h"

namespace caustic {

// The study (docs/study/README.md) measured these on every example scene: the sobol sampler with
// 16 samples per pass reaches a given path-tracing error sooner than independent numbers, and the
// error target stops a render as soon as it is met (spp is then only a ceiling).
const std::vector<Preset>& presets() {
    static const std::vector<Preset> table = {
        {"draft",
         "A quick look: at most 16 spp, stopping at 10% relative error.",
         {{"spp", 16}, {"spp_per_pass", 4}, {"sampler", "sobol"}, {"target_error", 0.1}}},
        {"preview",
         "Good enough to judge light and materials: at most 256 spp, stopping at 3%.",
         {{"spp", 256}, {"spp_per_pass", 16}, {"sampler", "sobol"}, {"target_error", 0.03}}},
        {"final",
         "For the record: at most 8192 spp, stopping at 1% relative error.",
         {{"spp", 8192}, {"spp_per_pass", 64}, {"sampler", "sobol"}, {"target_error", 0.01}}},
    };
    return table;
}

nlohmann::json presetSettings(const nlohmann::json& name) {
    if (name.is_string())
        for (const Preset& p : presets())
            if (p.name == name.get<std::string>()) return p.settings;
    return nlohmann::json::object();
}

}  // namespace caustic
