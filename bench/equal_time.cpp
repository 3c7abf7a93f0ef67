// Equal-time comparison of `path`, `photon` and `ppm` on cornell-spheres: each integrator gets the
// same wall time (a time_limit with an spp it cannot reach), runs interleaved (path, photon, ppm,
// path, ...) because the machine is shared and noisy, and each image is compared with a long `path`
// reference (cached under the build directory, keyed by a hash of the renderer library): RMSE over
// the whole image and over the caustic the glass sphere focuses on the floor.
#include <omp.h>

#include "bench_common.h"
#include "reference.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "accel/accelerator.h"
#include "film/image_io.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace {

using namespace caustic::bench;
using caustic::Json;
using caustic::Vec3;

const std::vector<std::string> kIntegrators = {"path", "photon", "ppm"};

// The settings a user would pick for a time-limited render, before --set overrides (bench/README.md
// lists the others measured). Passes of 4 spp: short against the budget, so that the pass cut off
// at the time limit wastes little; for photon and ppm, one photon tracing (about a second here)
// serves 4 camera samples, which halves their error against 1 spp per pass.
Json defaultSettings(const std::string& integrator) {
    if (integrator == "path") return {{"spp_per_pass", 4}};
    if (integrator == "photon")
        return {{"spp_per_pass", 4}, {"photons", 200000}, {"caustic_photons", 1000000}, {"k", 50}};
    return {{"spp_per_pass", 4},
            {"photons", 100000},
            {"caustic_photons", 1000000},
            {"radius", 0.03},
            {"alpha", 2.0 / 3.0}};
}

struct Options {
    std::vector<double> budgets = {10, 30, 90};
    int repeats = 1;
    int size = 128;
    int refSpp = 32768;
    std::vector<std::string> integrators = {"path", "photon", "ppm"};
    std::map<std::string, Json> settings;  // per integrator, defaults with --set applied
};

// `--set INTEGRATOR.KEY=VALUE`: sets one setting of one integrator (checked when it renders).
void setIntegratorSetting(const std::string& text, Options& o) {
    size_t dot = text.find('.'), eq = text.find('=');
    if (dot == std::string::npos || eq == std::string::npos || eq < dot ||
        !o.settings.count(text.substr(0, dot)))
        throw CLI::ValidationError("--set",
                                   "expected INTEGRATOR.KEY=VALUE with INTEGRATOR path, "
                                   "photon or ppm, got \"" +
                                       text + "\"");
    o.settings[text.substr(0, dot)][text.substr(dot + 1, eq - dot - 1)] =
        caustic::parseSettingValue(text.substr(eq + 1));
}

// Parses the command line into `o`; returns -1 to run, else the exit code.
int parseArgs(int argc, char** argv, Options& o) {
    for (const std::string& name : kIntegrators) o.settings[name] = defaultSettings(name);
    CLI::App app("path, photon and ppm at equal time against a path-traced reference.",
                 "bench_equal_time");
    bool smoke = false;
    addCommonOptions(app, o.repeats, "Interleaved rounds (path, photon, ppm) per budget; medians",
                     smoke, "32x32, 1-second budget, 256-spp reference");
    caustic::cli::addNumber(app, "--seconds", o.budgets, 0.001, 1e6,
                            "Time budgets, seconds of wall time per render, comma-separated");
    caustic::cli::addNumber(app, "--size", o.size, 1, 16384, "Square resolution");
    caustic::cli::addNumber(app, "--ref-spp", o.refSpp, 1, 1e6,
                            "Samples per pixel of the path-traced reference");
    app.add_option("--integrators", o.integrators,
                   "Which to run, comma-separated, in this order; ratios are to the first")
        ->delimiter(',')
        ->check(CLI::IsMember(kIntegrators))
        ->type_name("LIST")
        ->capture_default_str();
    app.add_option_function<std::string>(
           "--set", [&o](const std::string& text) { setIntegratorSetting(text, o); },
           "Sets setting KEY of integrator I, e.g. ppm.radius=0.05 (repeatable)")
        ->type_name("I.KEY=VALUE")
        ->trigger_on_parse();
    if (int exitCode = parseBenchmarkArgs(app, argc, argv); exitCode >= 0) return exitCode;
    if (smoke) {
        o.budgets = {1};
        o.repeats = 1;
        o.size = 32;
        o.refSpp = 256;
    }
    return -1;
}

// Full, validated settings of one render (parseSettings throws for a bad --set).
caustic::RenderSettings renderSettings(const std::string& integrator, const Json& overrides,
                                       double budget, uint64_t seed) {
    Json s = overrides;
    s["integrator"] = integrator;
    s["spp"] = 1000000;  // the most allowed: the time limit ends the render
    s["time_limit"] = budget;
    s["seed"] = seed;
    return caustic::parseSettings(s, "/" + integrator);
}

// The settings that matter to `integrator`: those the settings table says it reads, and the pass
// size. For the output.
std::string describe(const caustic::RenderSettings& s) {
    const Json all = s.toJson();
    std::string text = "spp_per_pass=" + all["spp_per_pass"].dump();
    for (const caustic::SettingSpec& spec : caustic::settingSpecs()) {
        const auto& in = spec.integrators;
        if (std::find(in.begin(), in.end(), s.integrator) != in.end() || spec.name == "max_depth")
            text += ", " + spec.name + "=" + all[spec.name].dump();
    }
    return text;
}

Vec3 vec3(const Json& j) {
    return Vec3(j[0].get<float>(), j[1].get<float>(), j[2].get<float>());
}

// The caustic region: the pixels whose camera ray (through the pixel centre) first hits the floor
// within `radius` of `centre`. The centre is where the ray from the light's centre through the
// glass sphere's centre meets the floor (that ray is not bent). The radius: an exact Snell trace
// (no Fresnel) of 2e5 rays from points of the light through the sphere put 95% of their floor hits
// within 0.138 and 99% within 0.157 of the centre; 0.15 takes the whole caustic with little else.
// Part of the disk lies under the sphere and is seen only through the glass: not in the region.
struct Region {
    Vec3 centre{0.0f};
    float radius = 0.15f, floorY = 0;
    std::vector<char> mask;  // per pixel
    int pixels = 0, x0 = 1 << 30, x1 = -1, y0 = 1 << 30, y1 = -1;
};

Region causticRegion(const Json& doc, const caustic::Scene& scene) {
    const Json& materials = doc["materials"];
    std::optional<Vec3> glass, light, floor;
    for (const Json& shape : doc["shapes"]) {
        const Json& m = materials[shape["material"].get<std::string>()];
        if (shape["type"] == "sphere" && m["type"] == "dielectric") {
            glass = vec3(shape["center"]);
        } else if (shape["type"] == "quad" && m.contains("emission")) {
            light = vec3(shape["origin"]) + 0.5f * (vec3(shape["u"]) + vec3(shape["v"]));
        } else if (shape["type"] == "quad" && shape["u"][1] == 0 && shape["v"][1] == 0 &&
                   (!floor || shape["origin"][1].get<float>() < floor->y)) {
            floor = vec3(shape["origin"]);
        }
    }
    if (!glass || !light || !floor)
        throw std::runtime_error("the scene needs a glass sphere, a quad light and a floor quad");
    Region r;
    r.floorY = floor->y;
    const Vec3 d = *glass - *light;
    r.centre = *light + d * ((r.floorY - light->y) / d.y);

    const caustic::Camera& camera = scene.camera;
    const Vec3 cameraPosition = vec3(doc["camera"]["position"]);
    auto accel = caustic::createAccelerator(caustic::RenderSettings{}.accelerator, scene.geometry);
    r.mask.assign(size_t(camera.width()) * size_t(camera.height()), 0);
    for (int y = 0; y < camera.height(); ++y)
        for (int x = 0; x < camera.width(); ++x) {
            caustic::Ray ray = camera.generateRay(float(x) + 0.5f, float(y) + 0.5f);
            std::optional<caustic::Hit> hit = accel->intersect(ray, caustic::kInfinity);
            if (!hit) continue;
            // The loader stores positions relative to the camera.
            Vec3 p = cameraPosition + ray.o + hit->t * ray.d;
            if (std::abs(p.y - r.floorY) > 1e-3f ||
                std::hypot(p.x - r.centre.x, p.z - r.centre.z) > r.radius)
                continue;
            r.mask[size_t(y) * size_t(camera.width()) + size_t(x)] = 1;
            ++r.pixels;
            r.x0 = std::min(r.x0, x), r.x1 = std::max(r.x1, x);
            r.y0 = std::min(r.y0, y), r.y1 = std::max(r.y1, y);
        }
    if (r.pixels == 0) throw std::runtime_error("the caustic region has no pixels");
    return r;
}

// The figures of one render; medians over repeats keep this shape.
struct Figures {
    double passes, spp, seconds, rmseAll, rmseRegion, netRegion, relRegion, meanRatio, noiseRegion,
        biasRegion, noiseAll, biasAll;
};

Figures measure(const caustic::RenderResult& r, const Reference& ref, const Region& region) {
    const std::vector<float> mean = r.film->meanRgb(), se = r.film->standardErrorRgb();
    Sums all, in;
    for (size_t i = 0; i < mean.size(); ++i) {
        all.add(mean[i], se[i], ref.mean[i], ref.se[i]);
        if (region.mask[i / 3]) in.add(mean[i], se[i], ref.mean[i], ref.se[i]);
    }
    return {double(r.stats.passes),
            double(r.stats.sppReached),
            r.stats.totalSeconds,
            all.rmse(),
            in.rmse(),
            in.rmseLessReference(),
            in.relativeLessReference(),
            in.img / in.ref,
            in.noise(),
            in.bias(),
            all.noise(),
            all.bias()};
}

Figures medianFigures(const std::vector<Figures>& runs) {
    Figures m{};
    double* out = &m.passes;
    for (size_t f = 0; f < sizeof(Figures) / sizeof(double); ++f) {
        std::vector<double> v;
        for (const Figures& r : runs) v.push_back((&r.passes)[f]);
        out[f] = median(v);
    }
    return m;
}

std::string loadAverage() {
    std::ifstream in("/proc/loadavg");
    std::string a, b, c;
    in >> a >> b >> c;
    return a + " " + b + " " + c;
}

// The reference for `scene`: loaded from the cache, else rendered and saved.
Reference reference(const caustic::Scene& scene, const Json& doc, const Options& opt,
                    std::filesystem::path& file) {
    caustic::RenderSettings s;
    s.integrator = "path";
    s.spp = opt.refSpp;
    s.seed = 1000003;  // the timed runs use seeds 1, 2, ...
    return cachedReference(
        scene, doc, s, std::filesystem::read_symlink("/proc/self/exe").parent_path() / "equal_time",
        CAUSTIC_RENDERER_LIBRARY, &file);
}

// The reference as a PNG beside its cache file, and again with the caustic region tinted.
void writePreviews(const std::filesystem::path& file, const Reference& ref, const Region& region,
                   int size) {
    caustic::RgbImage image{size, size, ref.mean};
    caustic::writeImage(std::filesystem::path(file).replace_extension(".png"), image);
    for (size_t p = 0; p < region.mask.size(); ++p)
        if (region.mask[p]) image.pixels[3 * p + 2] += 0.5f;
    caustic::writeImage(std::filesystem::path(file).replace_extension(".region.png"), image);
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    if (int exitCode = parseArgs(argc, argv, opt); exitCode >= 0) return exitCode;

    try {
        // Load the scene at the benchmark's resolution; find the caustic region.
        Json doc = caustic::readJsonFile(std::string(CAUSTIC_DEFAULT_SCENES_DIR) +
                                         "/cornell-spheres.json");
        doc["camera"]["width"] = opt.size;
        doc["camera"]["height"] = opt.size;
        auto scene = caustic::loadScene(doc, caustic::SceneOptions{CAUSTIC_DEFAULT_ASSETS_DIR});
        const Region region = causticRegion(doc, *scene);

        // The reference, and its own noise.
        std::filesystem::path refFile;
        const Reference ref = reference(*scene, doc, opt, refFile);
        writePreviews(refFile, ref, region, opt.size);
        Sums refAll, refIn;
        for (size_t i = 0; i < ref.mean.size(); ++i) {
            refAll.add(ref.mean[i], ref.se[i], ref.mean[i], 0);
            if (region.mask[i / 3]) refIn.add(ref.mean[i], ref.se[i], ref.mean[i], 0);
        }

        std::cout << "### Equal time on cornell-spheres, " << opt.size << "x" << opt.size
                  << ": path, photon, ppm against a path-traced reference\n\n"
                  << "- Reference: `path`, " << opt.refSpp << " spp in " << ref.passes
                  << " passes, seed 1000003, " << fmt("%.0f", ref.seconds)
                  << " s when rendered; cache `" << refFile.string() << "` (beside it: `.png`, "
                  << "and `.region.png` with the region tinted blue). Its noise, the RMS standard "
                  << "error of its passes: overall " << fmt("%.5f", refAll.noise()) << " ("
                  << fmt("%.2f%%", 100 * refAll.relativeNoise())
                  << " of the RMS pixel value), caustic region " << fmt("%.5f", refIn.noise())
                  << " (" << fmt("%.2f%%", 100 * refIn.relativeNoise()) << ").\n"
                  << "- Caustic region: floor pixels (camera ray through the pixel centre hits the "
                  << "floor first) within " << fmt("%.2f", region.radius) << " of ("
                  << fmt("%.3f", region.centre.x) << ", " << fmt("%.3f", region.centre.y) << ", "
                  << fmt("%.3f", region.centre.z) << "), where the light's centre projects through "
                  << "the glass sphere's centre: " << region.pixels << " pixels in x " << region.x0
                  << "–" << region.x1 << ", y " << region.y0 << "–" << region.y1 << " (0-based, "
                  << "top row 0).\n"
                  << "- Budgets (s): ";
        for (size_t b = 0; b < opt.budgets.size(); ++b)
            std::cout << (b ? ", " : "") << fmt("%g", opt.budgets[b]);
        std::cout << "; each a `time_limit` with spp 10^6, " << opt.repeats
                  << " interleaved round(s) per budget (medians), every OpenMP thread ("
                  << omp_get_max_threads() << "), seeds 1, 2, ...\n";
        for (const std::string& name : opt.integrators)
            std::cout << "- `" << name
                      << "`: " << describe(renderSettings(name, opt.settings.at(name), 1, 0))
                      << "\n";
        std::cout << std::endl;

        // Interleave the integrators within every round of every budget.
        const std::string loadBefore = loadAverage();
        std::map<std::pair<double, std::string>, std::vector<Figures>> runs;
        uint64_t seed = 1;
        for (double budget : opt.budgets)
            for (int rep = 0; rep < opt.repeats; ++rep, ++seed)
                for (const std::string& name : opt.integrators) {
                    caustic::RenderResult r = caustic::render(
                        *scene, renderSettings(name, opt.settings.at(name), budget, seed));
                    runs[{budget, name}].push_back(measure(r, ref, region));
                    std::cerr << "done " << name << " " << budget << " s, round " << rep + 1
                              << "\n";
                }

        // The comparison, then the caustic's error split into bias and noise.
        std::cout << "RMSE: over every pixel and channel, against the reference; caustic: over the "
                     "region. Less ref. noise: √(MSE − reference noise²), what the RMSE against "
                     "the true image would be (the reference's noise adds to the squared error). "
                     "÷ path: the column to its left over path's. Rel.: the caustic RMSE less "
                     "reference noise over the RMS reference value in the region. Seconds: the "
                     "whole render, setup included.\n\n"
                  << "| budget s | integrator | passes | spp | seconds | RMSE | ÷ path | RMSE "
                     "caustic | less ref. noise | ÷ path | rel. |\n"
                  << "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        for (double budget : opt.budgets) {
            // Without path (--integrators), the ratios are against the first integrator.
            const Figures path = medianFigures(runs[{budget, opt.integrators[0]}]);
            for (const std::string& name : opt.integrators) {
                const Figures f = medianFigures(runs[{budget, name}]);
                std::cout << "| " << fmt("%g", budget) << " | " << name << " | "
                          << fmt("%.0f", f.passes) << " | " << fmt("%.0f", f.spp) << " | "
                          << fmt("%.1f", f.seconds) << " | " << fmt("%.5f", f.rmseAll) << " | "
                          << fmt("%.2f", f.rmseAll / path.rmseAll) << " | "
                          << fmt("%.4f", f.rmseRegion) << " | " << fmt("%.4f", f.netRegion) << " | "
                          << (path.netRegion > 0 ? fmt("%.2f", f.netRegion / path.netRegion) : "—")
                          << " | " << fmt("%.1f%%", 100 * f.relRegion) << " |\n";
            }
        }
        std::cout << "\n**Bias and noise.** Noise: the run's own RMS standard error (from the "
                     "spread of its passes; a rough figure for ppm, whose passes differ). Bias: "
                     "√(MSE − noise² − reference noise²), what the error leaves beyond both "
                     "images' noise. Caustic mean: the region's mean over the reference's.\n\n"
                  << "| budget s | integrator | caustic mean ÷ ref | caustic noise | caustic bias "
                     "| overall noise | overall bias |\n"
                  << "|---:|---|---:|---:|---:|---:|---:|\n";
        for (double budget : opt.budgets)
            for (const std::string& name : opt.integrators) {
                const Figures f = medianFigures(runs[{budget, name}]);
                // One pass has no spread to estimate its noise from.
                auto split = [&](const char* format, double v) {
                    return f.passes >= 2 ? fmt(format, v) : std::string("—");
                };
                std::cout << "| " << fmt("%g", budget) << " | " << name << " | "
                          << fmt("%.3f", f.meanRatio) << " | " << split("%.4f", f.noiseRegion)
                          << " | " << split("%.4f", f.biasRegion) << " | "
                          << split("%.5f", f.noiseAll) << " | " << split("%.5f", f.biasAll)
                          << " |\n";
            }
        std::cout << "\nLoad average before the timed runs: " << loadBefore
                  << "; after: " << loadAverage() << ".\n";
    } catch (const std::exception& e) {
        std::cerr << "bench_equal_time: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
