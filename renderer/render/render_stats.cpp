#include "render/render_stats.h"

#include <cmath>

namespace caustic {

nlohmann::json MemoryStats::toJson() const {
    return {{"geometry", geometry},        {"meshes", meshes},
            {"accelerator", accelerator},  {"film", film},
            {"light_tables", lightTables}, {"photon_maps", photonMaps},
            {"textures", textures},        {"total", total()}};
}

nlohmann::json RenderStats::toJson() const {
    auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
    return {{"setup_seconds", setupSeconds},
            {"accelerator_seconds", acceleratorSeconds},
            {"integrator_seconds", integratorSeconds},
            {"render_seconds", renderSeconds},
            {"pass_setup_seconds", passSetupSeconds},
            {"total_seconds", totalSeconds},
            {"rays", rays},
            {"samples", samples},
            {"rays_per_second", raysPerSecond},
            {"passes", passes},
            {"spp", sppReached},
            {"relative_error", number(relativeError)},
            {"relative_noise", number(relativeNoise)},
            {"relative_bias", number(relativeBias)},
            {"dropped_samples", droppedSamples},
            {"clamped_values", clampedValues},
            {"threads", threads},
            {"stop_reason", toString(stopReason)},
            {"memory", memory.toJson()},
            {"built", builtJson()}};
}

nlohmann::json RenderStats::builtJson() const {
    nlohmann::json parts = nlohmann::json::array();
    for (const BuiltPart& p : built)
        parts.push_back(
            {{"part", p.part}, {"seconds", p.seconds}, {"bytes", p.bytes}, {"count", p.count}});
    return parts;
}

}  // namespace caustic
