#include "render/presets.h"

namespace caustic {

// From the study (bench_study, docs/study/README.md: 96x96, every example scene, path tracing).
// Preview's settings (adaptive sampling from an 8-pass pilot, 8 per pass) reached each scene's
// target RMSE 1.43 to 3.27 times sooner than path with independent numbers: the fastest of all on
// the bunny (photon maps, or sobol at 16 a pass, win on the others). But adaptive sampling starves
// dark pixels (uniform sampling's relative MSE is 0.63 to 0.93 times its), so final, whose dark
// corners matter, samples uniformly with 16 per pass (1.31 to 3.16 times path's speed); draft stops
// before the pilot ends. The error target stops each as soon as it is met, spp being a ceiling.
// None takes a photon map: their bias is outside the error the target reads.
//
// All three run one Sobol' sequence through a pixel's passes (sobol_sequence). Each pass is then
// the same net as with sobol, so the passes' spread, and with it the reported error and the pass
// at which the target stops a render, are about the same; but the passes fill each other's gaps,
// so the image is truer than that spread says. Measured at 128x128, 2 seeds, against 4096-spp
// references (bench/preset_stops.sh): on the bunny and cornell-box the true error at the stop is
// 3 to 8% lower than with sobol at the same pass, on cornell-spheres (glass) from 2% higher to 4%
// lower, within a pass; the reported error is then 1.01 to 1.10 times the true one, an estimate on
// the safe side.
const std::vector<Preset>& presets() {
    static const std::vector<Preset> table = {
        {"draft",
         "A quick look: at most 16 spp, stopping at 10% relative error.",
         {{"spp", 16}, {"spp_per_pass", 4}, {"sampler", "sobol_sequence"}, {"target_error", 0.1}}},
        {"preview",
         "Good enough to judge light and materials: adaptive sampling, at most 256 spp, stopping "
         "at 3%.",
         {{"spp", 256},
          {"spp_per_pass", 8},
          {"sampler", "sobol_sequence"},
          {"adaptive", true},
          {"target_error", 0.03}}},
        {"final",
         "For the record: uniform sampling, at most 8192 spp, stopping at 1% relative error.",
         {{"spp", 8192},
          {"spp_per_pass", 16},
          {"sampler", "sobol_sequence"},
          {"adaptive", false},
          {"target_error", 0.01}}},
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
