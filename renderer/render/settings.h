// Render settings: one table describes every setting (type, default, range, unit, which integrators
// read it), and every reader (scene files, the CLI's --set, the server, the web page) goes through
// it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace caustic {

using Json = nlohmann::json;

/// The validated settings of one render. Field names follow the JSON keys.
struct RenderSettings {
    std::string integrator = "path";
    int spp = 16;                ///< Samples per pixel: the most the render takes.
    int sppPerPass = 0;          ///< Samples per pixel in each pass; 0 chooses automatically.
    double timeLimit = 0;        ///< Seconds; 0 for none.
    double targetError = 0;      ///< Relative RMS error to stop at; 0 for none.
    int maxDepth = 16;           ///< Most bounces on a path (scattering events); Whitted recursion.
    int rrDepth = 3;             ///< Path tracing: bounces before Russian roulette may end a path.
    bool lightSampling = true;   ///< Path tracing: next-event estimation.
    bool mis = true;             ///< Path tracing: power-heuristic MIS of light and BSDF samples.
    int64_t photons = 200000;    ///< Photon mapping: photon paths traced per pass.
    int64_t causticPhotons = 0;  ///< Photon mapping: caustic-map paths per pass; 0 shares.
    std::string photonLookup = "kdtree";  ///< Photon mapping: "kdtree" or "brute_force".
    int k = 50;                           ///< Photon mapping: photons per density estimate.
    double radius = 0;            ///< Photon mapping: fixed search radius; 0 uses the k nearest.
    std::string kernel = "cone";  ///< Photon mapping: density-estimation kernel.
    int finalGather = 0;          ///< Photon mapping: final-gather rays per camera path.
    double alpha = 2.0 / 3.0;     ///< Progressive photon mapping: radius reduction per pass.
    std::string accelerator = "embree";  // the fastest of the three today
    double memoryLimit = 0;              ///< MiB; 0 for half the machine's physical memory.
    uint64_t seed = 0;
    int threads = 0;      ///< 0 uses every core.
    double exposure = 0;  ///< Stops (powers of two) applied to PNG output.

    /// Samples per pass after resolving 0: the largest divisor of spp no greater than spp / 64, so
    /// that a render has about 64 equal passes (every pass when spp < 64).
    int resolvedSppPerPass() const;
    /// memory_limit in bytes, with 0 resolved to half the physical memory.
    size_t memoryLimitBytes() const;
    Json toJson() const;
};

enum class SettingType { Integer, Number, Boolean, String };

struct SettingSpec {
    std::string name;
    SettingType type;
    Json defaultValue;
    double min = 0, max = 0;           ///< Inclusive range for numbers.
    std::vector<std::string> choices;  ///< Valid values for strings.
    std::string unit;
    std::string description;
    std::vector<std::string> integrators;  ///< Integrators that read it; empty for all.
};

/// Every setting, in documentation order.
const std::vector<SettingSpec>& settingSpecs();
/// The table as JSON: {name: {type, default, minimum, maximum, enum, unit, description,
/// integrators}}, for the API and the web page.
Json settingsSchemaJson();

/// Overlays `overrides` on `defaults` (both objects of settings), key by key.
Json mergeSettings(const Json& defaults, const Json& overrides);
/// Validates a settings object against the table and fills RenderSettings. Unknown keys, wrong
/// types, and values out of range are InputErrors with the path `path`/key.
RenderSettings parseSettings(const Json& settings, const std::string& path = "/settings");
/// Parses the value of a command-line `key=value`: JSON when it parses as JSON, else a string.
Json parseSettingValue(const std::string& text);

}  // namespace caustic
