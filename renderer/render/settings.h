// Render settings. One table (render/settings_table.cpp) declares every setting once: its name,
// the field it is stored in, range, unit, the integrators that read it and its doc; the type and
// default come from the field. Parsing (scene files, the CLI's --set, the server), defaults, JSON
// output, the schema behind /api/settings, `caustic settings` and the web form all derive from it.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "integrators/integrator.h"
#include "integrators/path.h"
#include "integrators/photon.h"

namespace caustic {

using Json = nlohmann::json;

struct SettingSpec;
struct SceneTraits;

/// The validated settings of one render: the general ones (TraceSettings holds maxDepth, seed and
/// threads, which integrators read too), then each integrator's own Settings.
struct RenderSettings : TraceSettings {
    /// The preset the settings started from (render/presets.h); auto where none is named.
    std::string preset = "auto";
    std::string integrator = "path";
    int spp = 16;            ///< Samples per pixel: the most the render takes.
    int sppPerPass = 0;      ///< Samples per pixel in each pass; 0 chooses.
    double timeLimit = 0;    ///< Seconds; 0 for none.
    double targetError = 0;  ///< Relative RMS error to stop at; 0 for none.
    SamplerKind sampler = SamplerKind::Independent;
    bool adaptive = false;  ///< Samples by each pixel's error after a pilot (render/sample_map.h).
    /// Camera rays per sample for the emission seen directly (render/seen_emission.h); 0: the
    /// sample's own ray.
    int emissionSamples = 8;
    std::string accelerator = "embree";  // the fastest of the three (bench/README.md)
    double memoryLimit = 0;              ///< MiB; 0 for half the machine's physical memory.
    double exposure = 0;                 ///< Stops (powers of two) applied to PNG output.
    /// The image's size in pixels over the scene camera's; 0 keeps the camera's (see
    /// render/resolution.h, which also resolves them to the size rendered).
    int width = 0, height = 0;
    PathIntegrator::Settings path;      ///< What `path` reads besides TraceSettings.
    PhotonIntegrator::Settings photon;  ///< What `photon` and `ppm` read besides TraceSettings.

    /// Samples per pass after resolving 0: the largest divisor of spp no greater than spp / 64, so
    /// that a render has about 64 equal passes (every pass when spp < 64).
    int resolvedSppPerPass() const;
    /// The passes of a render: spp / resolvedSppPerPass(), rounded up (an spp_per_pass that does
    /// not divide spp takes a last whole pass). Every count of passes comes from here.
    int passesTotal() const;
    /// memory_limit in bytes, with 0 resolved to half the physical memory.
    size_t memoryLimitBytes() const;
    /// The general settings and those `integrator` reads, by JSON name; parseSettings takes it
    /// back.
    Json toJson() const;
    /// Whether these settings' integrator reads the setting.
    bool reads(const SettingSpec& spec) const;
};

enum class SettingType { Integer, Number, Boolean, String };

/// Which of a render service's limits caps a setting (the service's --max-spp, --max-photons,
/// --max-time-limit, --max-memory-mib): admission holds every setting a job's integrator reads to
/// its cap, so a setting gets the same cap whichever integrator reads it.
enum class SettingCap { None, Spp, Photons, Seconds, MemoryMiB };
/// "integer", "number", "boolean" or "string": the JSON Schema type.
const char* toString(SettingType type);

/// Binds a setting to its RenderSettings field (made by the table's `field`). `choices` are the
/// row's: an enum field is stored as the index of its name in them.
struct SettingField {
    SettingType type = SettingType::Integer;
    std::function<Json(const RenderSettings&, const std::vector<std::string>& choices)> get{};
    /// Stores a value that validation accepted (an integer, number, boolean or valid choice).
    std::function<void(RenderSettings&, const Json&, const std::vector<std::string>& choices)>
        set{};
};

/// One row of the table. `type` and `defaultValue` are derived from `field` (its C++ type, and
/// its value in a default RenderSettings); the rest is written in the row. Every member has a
/// default initializer, so that a row names only what it sets (GCC 12 warns of omitted
/// designated initializers otherwise).
struct SettingSpec {
    std::string name{};
    SettingField field{};
    SettingType type = SettingType::Integer;
    Json defaultValue{};
    double min = 0, max = 0;             ///< Inclusive range for numbers.
    std::vector<std::string> choices{};  ///< Valid values for strings.
    std::string unit{};
    std::vector<std::string> integrators{};  ///< Integrators that read it; empty for all.
    /// A setting that path reads only for its photon maps: a set of kCausticMap (caustics =
    /// photon_map) and kIndirectMap (indirect = photon_map), one of which must be on; 0 when path
    /// reads it whenever `integrators` names it.
    unsigned pathMaps = 0;
    static constexpr unsigned kCausticMap = 1, kIndirectMap = 2;
    SettingCap cap = SettingCap::None;  ///< The service's limit on it, if any.
    std::string description{};

    /// Whether `integrator` (a name) reads it.
    bool readBy(const std::string& integrator) const;
};

/// Every setting, in documentation order.
const std::vector<SettingSpec>& settingSpecs();
/// The table as JSON: {name: {type, default, minimum, maximum, enum, unit, description,
/// integrators, only_with}}, for the API and the web page. only_with, when present, maps an
/// integrator to the alternative settings it must have for it to read this one, each an object of
/// values: {"path": [{"caustics": "photon_map"}, {"indirect": "photon_map"}]} on the photon
/// settings that both of path's maps read.
Json settingsSchemaJson();

/// Overlays `overrides` on `defaults` (both objects of settings), key by key, with the preset that
/// `overrides` names (else the one `defaults` names) between them: a preset replaces the defaults'
/// values for what it sets, and `overrides` replace the preset's (render/presets.h). With the
/// scene's `traits`, a preset that takes photon maps takes those the scene needs. A preset's
/// spp_per_pass shrinks to leave spp at least 8 passes where it can.
Json mergeSettings(const Json& defaults, const Json& overrides,
                   const SceneTraits* traits = nullptr);
/// Validates a settings object against the table and fills RenderSettings. Every setting is
/// accepted whichever the integrator (a scene's defaults may serve several). Unknown keys, wrong
/// types, and values out of range are InputErrors with the path `path`/key.
RenderSettings parseSettings(const Json& settings, const std::string& path = "/settings");
/// Parses the value of a command-line `key=value`: JSON when it parses as JSON, else a string.
Json parseSettingValue(const std::string& text);

}  // namespace caustic
