// The settings table: each render setting declared once, as a row naming the field that stores it.
// A new setting is a field (its C++ type and default) and a row here; parsing, JSON output, the
// schema, `caustic settings`, the CLI's --set and the web form follow from them.
#include <algorithm>
#include <cstdint>
#include <string>
#include <type_traits>

#include "accel/accelerator.h"
#include "render/integrator_factory.h"
#include "render/presets.h"
#include "render/settings.h"

namespace caustic {
namespace {

template <class T>
constexpr SettingType settingTypeOf() {
    static_assert(std::is_arithmetic_v<T> || std::is_enum_v<T> || std::is_same_v<T, std::string>,
                  "a setting is a number, a boolean, a string or an enum");
    if constexpr (std::is_same_v<T, bool>)
        return SettingType::Boolean;
    else if constexpr (std::is_integral_v<T>)
        return SettingType::Integer;
    else if constexpr (std::is_floating_point_v<T>)
        return SettingType::Number;
    else
        return SettingType::String;
}

// The member that a chain of member pointers leads to: s.*m, then .*ms in turn.
template <class S, class M, class... Ms>
auto& member(S& s, M m, Ms... ms) {
    if constexpr (sizeof...(Ms) == 0)
        return s.*m;
    else
        return member(s.*m, ms...);
}

// The binding of the field that `members` lead to from a RenderSettings (`&R::spp`, or
// `&R::path, &PathIntegrator::Settings::mis`). Integers are read as int64 and numbers as double,
// as validation returns them; an enum is its name in the row's choices.
template <class... Members>
SettingField field(Members... members) {
    using T = std::remove_cvref_t<decltype(member(std::declval<RenderSettings&>(), members...))>;
    SettingField f;
    f.type = settingTypeOf<T>();
    f.get = [=](const RenderSettings& s, const std::vector<std::string>& choices) -> Json {
        const T& v = member(s, members...);
        if constexpr (std::is_enum_v<T>)
            return choices.at(size_t(v));
        else if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, std::string>)
            return v;
        else if constexpr (std::is_integral_v<T>)
            return int64_t(v);
        else
            return double(v);
    };
    f.set = [=](RenderSettings& s, const Json& v, const std::vector<std::string>& choices) {
        T& out = member(s, members...);
        if constexpr (std::is_enum_v<T>)
            out = T(std::find(choices.begin(), choices.end(), v.get<std::string>()) -
                    choices.begin());
        else if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, std::string>)
            out = v.get<T>();
        else if constexpr (std::is_integral_v<T>)
            out = static_cast<T>(v.get<int64_t>());
        else
            out = static_cast<T>(v.get<double>());
    };
    return f;
}

std::vector<std::string> presetNames() {
    std::vector<std::string> names = {"none"};
    for (const Preset& p : presets()) names.push_back(p.name);
    return names;
}

std::vector<SettingSpec> rows() {
    using R = RenderSettings;
    using Path = PathIntegrator::Settings;
    using Photon = PhotonIntegrator::Settings;
    const std::vector<std::string> tracers = {"whitted", "path", "photon", "ppm"};
    const std::vector<std::string> photonMappers = {"photon", "ppm"};
    // What path reads too, with caustics = photon_map (and `both`: or indirect = photon_map).
    const std::vector<std::string> causticMappers = {"path", "photon", "ppm"};
    const unsigned caustic = SettingSpec::kCausticMap;
    const unsigned both = SettingSpec::kCausticMap | SettingSpec::kIndirectMap;
    return {
        {.name = "preset",
         .field = field(&R::preset),
         .choices = presetNames(),
         .description = "Named settings from the speed/accuracy study. auto (the default) chooses "
                        "photon maps, sampler and pass size from what the scene holds, beneath "
                        "the scene's own settings; draft, preview and final also set how long "
                        "to render, and replace the scene's own. Every setting given beside a "
                        "preset replaces the preset's. none: the scene's settings and the "
                        "defaults."},
        {.name = "integrator",
         .field = field(&R::integrator),
         .choices = integratorNames(),
         .description = "Light transport algorithm."},
        {.name = "spp",
         .field = field(&R::spp),
         .min = 1,
         .max = 1e6,
         .unit = "samples/pixel",
         .cap = SettingCap::Spp,
         .description = "Samples per pixel; the render stops when it has taken them all."},
        {.name = "spp_per_pass",
         .field = field(&R::sppPerPass),
         .min = 0,
         .max = 1e6,
         .unit = "samples/pixel",
         .description = "Samples per pixel in each pass (one independent estimate of the image). "
                        "0 chooses about 64 equal passes. Error estimates need at least 2 passes."},
        {.name = "time_limit",
         .field = field(&R::timeLimit),
         .min = 0,
         .max = 1e6,
         .unit = "s",
         .cap = SettingCap::Seconds,
         .description = "Stop after the pass that reaches this wall time; 0 for no limit."},
        {.name = "target_error",
         .field = field(&R::targetError),
         .min = 0,
         .max = 1,
         .description =
             "Stop once the estimated relative RMS error is at most this, from the second pass "
             "on (the eighth with a photon map); 0 for no target."},
        {.name = "max_depth",
         .field = field(&R::maxDepth),
         .min = 1,
         .max = 1e6,
         .unit = "bounces",
         .integrators = tracers,
         .description = "Most scattering events on a path (1: direct light only); for whitted, "
                        "the depth of specular recursion."},
        {.name = "rr_depth",
         .field = field(&R::path, &Path::rrDepth),
         .min = 1,
         .max = 1e6,
         .unit = "bounces",
         .integrators = {"path"},
         .description = "Bounces before Russian roulette may end a path (it continues with "
                        "probability equal to its throughput, so the estimate stays unbiased)."},
        {.name = "light_sampling",
         .field = field(&R::path, &Path::lightSampling),
         .integrators = {"path"},
         .description = "Sample a light (chosen by power) at every non-specular vertex. Off: the "
                        "naive path tracer, which finds emitters only by BSDF sampling and never "
                        "sees point lights."},
        {.name = "mis",
         .field = field(&R::path, &Path::mis),
         .integrators = {"path"},
         .description = "Weight light and BSDF samples by the power heuristic. Off (with "
                        "light_sampling on): direct light at non-specular vertices comes from "
                        "light samples only."},
        {.name = "caustics",
         .field = field(&R::path, &Path::caustics),
         .choices = {"paths", "photon_map"},  // PathSource' order
         .integrators = {"path"},
         .description = "Where caustics (light reaching a diffuse surface through mirrors and "
                        "glass only) come from. paths: path tracing alone (unbiased; a small "
                        "light seen through glass makes fireflies). photon_map: a caustic photon "
                        "map of `photons` paths a pass, read at every diffuse vertex with ppm's "
                        "shrinking radius (`radius`, `alpha`, `kernel`): consistent as ppm is, "
                        "with a bias that falls pass by pass and that the error estimate "
                        "includes; point lights' caustics appear too."},
        {.name = "indirect",
         .field = field(&R::path, &Path::indirect),
         .choices = {"paths", "photon_map"},  // PathSource's order
         .integrators = {"path"},
         .description = "Where the light leaving a path's second diffuse vertex comes from, other "
                        "than its emission and direct light. paths: path tracing (unbiased). "
                        "photon_map: the path ends there, with a light sample and a map of "
                        "`indirect_photons` photon paths a pass (the photons that scattered before "
                        "they landed), read with ppm's shrinking radius (`indirect_radius`, "
                        "`alpha`, `kernel`); the first diffuse vertex's BSDF sample is a final "
                        "gather, which hides the estimate's blur. Fewer rays a sample and less "
                        "noise from long paths; consistent as ppm is, with a bias that falls pass "
                        "by pass and that the error estimate includes."},
        {.name = "indirect_photons",
         .field = field(&R::path, &Path::indirectPhotons),
         .min = 1,
         .max = 1e9,
         .unit = "photon paths/pass",
         .integrators = {"path"},
         .pathMaps = SettingSpec::kIndirectMap,
         .cap = SettingCap::Photons,
         .description = "Photon paths traced from the lights in each pass for path's indirect "
                        "map (indirect = photon_map); it keeps the photons that scattered before "
                        "they landed (56 bytes each)."},
        {.name = "indirect_radius",
         .field = field(&R::path, &Path::indirectRadius),
         .min = 0,
         .max = 1e30,
         .unit = "scene units",
         .integrators = {"path"},
         .pathMaps = SettingSpec::kIndirectMap,
         .description =
             "The indirect map's radius in the first pass (it shrinks as ppm's, by "
             "`alpha`); 0 for 1/62.5 of the scene's diagonal (8 times the caustic map's)."},
        {.name = "photons",
         .field = field(&R::photon, &Photon::photons),
         .min = 1,
         .max = 1e9,
         .unit = "photon paths/pass",
         .integrators = causticMappers,
         .pathMaps = caustic,
         .cap = SettingCap::Photons,
         .description = "Photon paths traced from the lights in each pass (each stored photon "
                        "takes 56 bytes); path (caustics = photon_map): the caustic map's paths, "
                        "each ending at its first diffuse hit."},
        {.name = "caustic_photons",
         .field = field(&R::photon, &Photon::causticPhotons),
         .min = 0,
         .max = 1e9,
         .unit = "photon paths/pass",
         .integrators = photonMappers,
         .cap = SettingCap::Photons,
         .description = "Photon paths traced for the caustic map alone in each pass; each ends "
                        "at its first diffuse hit, so they are cheap. 0 takes the caustic "
                        "photons of the `photons` paths."},
        {.name = "photon_lookup",
         .field = field(&R::photon, &Photon::lookup),
         .choices = {"kdtree", "brute_force"},  // PhotonLookup's order
         .integrators = causticMappers,
         .pathMaps = both,
         .description = "Photon search structure: the kd-tree, or every photon for every look-up "
                        "(a baseline for benchmarks; the image is the same)."},
        {.name = "k",
         .field = field(&R::photon, &Photon::k),
         .min = 1,
         .max = 10000,
         .unit = "photons",
         .integrators = {"photon"},
         .description = "Photons per density estimate (the k nearest), when radius is 0."},
        {.name = "radius",
         .field = field(&R::photon, &Photon::radius),
         .min = 0,
         .max = 1e30,
         .unit = "scene units",
         .integrators = causticMappers,
         .pathMaps = caustic,
         .description = "photon: fixed density-estimation radius, 0 for the k nearest photons "
                        "instead; ppm and path's photon_map caustics: the first pass's radius, 0 "
                        "for 1/500 of the scene's diagonal."},
        {.name = "kernel",
         .field = field(&R::photon, &Photon::kernel),
         .choices = {"box", "cone", "simpson"},  // PhotonKernel's order
         .integrators = causticMappers,
         .pathMaps = both,
         .description = "Density-estimation kernel: box (uniform), cone (1 - d/r) or simpson "
                        "((1 - d^2/r^2)^2), each normalized over its disk."},
        {.name = "final_gather",
         .field = field(&R::photon, &Photon::finalGather),
         .min = 0,
         .max = 4096,
         .unit = "rays",
         .integrators = {"photon"},
         .description = "Final-gather rays per camera path for indirect light; 0 reads the "
                        "global photon map at the visible point."},
        {.name = "follow_roughness",
         .field = field(&R::photon, &Photon::followRoughness),
         .min = 0,
         .max = 1,
         .integrators = {"photon", "ppm"},
         .description = "Surfaces smoother than this roughness (glossy metals, rough glass) are "
                        "followed as mirrors: camera paths sample their BSDF and photons pass "
                        "them, instead of a density estimate there, which is noisy where the lobe "
                        "is narrow; 0 estimates every non-specular surface from the maps "
                        "(docs/integrators.md, Glossy surfaces)."},
        {.name = "alpha",
         .field = field(&R::photon, &Photon::alpha),
         .min = 0.01,
         .max = 1,
         .integrators = {"path", "ppm"},
         .pathMaps = both,
         .description = "Progressive photon mapping (ppm, and path's photon maps): pass "
                        "i's squared radius is the previous one "
                        "times (i - 1 + alpha) / i (Knaus & Zwicker 2011); smaller alpha shrinks "
                        "it faster."},
        {.name = "sampler",
         .field = field(&R::sampler),
         .choices = {"independent", "sobol", "sobol_sequence"},  // SamplerKind's order
         .description = "Random numbers of the pixel samples: independent (PCG32); sobol "
                        "(Owen-scrambled Sobol' points, padded: the samples of a pixel in one pass "
                        "are stratified in every pair of dimensions; each pass is an independent "
                        "randomization, so error estimates stay valid; it gains with more samples "
                        "per pass); or sobol_sequence (one scrambled Sobol' sequence runs through "
                        "all of a pixel's passes, so the error falls faster than 1/sqrt(spp), as "
                        "Cycles' sampler; the passes are then negatively correlated, so the "
                        "estimated error is an overestimate: target_error stops about where it "
                        "would with sobol, with a truer image; the presets use it)."},
        {.name = "adaptive",
         .field = field(&R::adaptive),
         .description = "Adaptive sampling: after 8 uniform pilot passes, each pass gives each "
                        "pixel samples in proportion to the noise the pilot measured there (at "
                        "least a quarter and at most 8 times spp_per_pass; the same total). The "
                        "image and its error estimate stay unbiased; it needs spp_per_pass of 4 or "
                        "more to move samples, and a render split after the pilot renders the "
                        "pilot again."},
        {.name = "emission_samples",
         .field = field(&R::emissionSamples),
         .min = 0,
         .max = 64,
         .unit = "rays/sample",
         .description = "Camera rays per sample that look for emitters seen directly through the "
                        "pixel: a lamp's edges, the noisiest pixels of an image with a lamp in "
                        "view, are resolved by spp times this many points. A ray costs a "
                        "traversal only where it meets an emitter's bounding box, so an emitter "
                        "that fills much of the view costs up to this many rays a sample in its "
                        "pixels: lower it there. 0: each sample's own ray (the background is "
                        "always the sample's own)."},
        {.name = "accelerator",
         .field = field(&R::accelerator),
         .choices = acceleratorNames(),
         .description = "Ray intersection structure."},
        {.name = "memory_limit",
         .field = field(&R::memoryLimit),
         .min = 0,
         .max = 1e9,
         .unit = "MiB",
         .cap = SettingCap::MemoryMiB,
         .description = "Refuse, before the first pass, a render whose estimated peak memory "
                        "(scene, accelerator, film, photon maps) exceeds this; 0 for half the "
                        "machine's memory."},
        {.name = "seed",
         .field = field(&R::seed),
         .min = 0,
         .max = 9007199254740991.0,  // 2^53 - 1: every seed is exact in a JSON number
         .description = "Random seed: the same scene, settings and seed give the same image."},
        {.name = "threads",
         .field = field(&R::threads),
         .min = 0,
         .max = 1024,
         .description = "Worker threads; 0 uses every core. The image does not depend on it."},
        {.name = "width",
         .field = field(&R::width),
         .min = 0,
         .max = 16384,
         .unit = "pixels",
         .description = "Image width, over the scene camera's. 0 keeps the camera's, or, when "
                        "only height is given, follows the camera's aspect ratio. The vertical "
                        "field of view stays the camera's."},
        {.name = "height",
         .field = field(&R::height),
         .min = 0,
         .max = 16384,
         .unit = "pixels",
         .description = "Image height, over the scene camera's. 0 keeps the camera's, or, when "
                        "only width is given, follows the camera's aspect ratio."},
        {.name = "exposure",
         .field = field(&R::exposure),
         .min = -20,
         .max = 20,
         .unit = "stops",
         .description =
             "Scales PNG output by 2^exposure before sRGB encoding; EXR output stays linear."},
    };
}

}  // namespace

const std::vector<SettingSpec>& settingSpecs() {
    static const std::vector<SettingSpec> specs = [] {
        std::vector<SettingSpec> table = rows();
        const RenderSettings defaults;
        for (SettingSpec& s : table) {
            s.type = s.field.type;
            s.defaultValue = s.field.get(defaults, s.choices);
        }
        return table;
    }();
    return specs;
}

bool SettingSpec::readBy(const std::string& integrator) const {
    return integrators.empty() ||
           std::find(integrators.begin(), integrators.end(), integrator) != integrators.end();
}

}  // namespace caustic
