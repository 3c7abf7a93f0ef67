// The speed/accuracy study (docs/study/; bench/study.sh runs it and makes the plots): every example
// scene, every integrator that converges to the path tracer's image and its key settings, each
// rendered once to the top of a ladder of samples per pixel; at every rung (a pass boundary: the
// image after N passes is the render of N passes, bit for bit) it records the time so far and the
// error against a long path-traced reference, over the image and over named regions, and how well
// the render's own error estimate tracks the true error. One CSV row per rung.
#include <omp.h>

#include "bench_common.h"
#include "reference.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "accel/accelerator.h"
#include "core/student_t.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace {

using namespace caustic::bench;
using caustic::Json;
using caustic::Vec3;

// The configurations compared: an integrator and the settings that matter to it. The ladder's
// rungs are samples per pixel; photon mappers trace their photons once per pass.
struct Config {
    std::string name;
    Json settings;
};

std::vector<Config> allConfigs() {
    // Photons per pass: a photon tracing of about a fifth of a second here serves 4 samples.
    const Json photons = {{"photons", 50000}, {"caustic_photons", 200000}};
    auto with = [&](Json settings) {
        settings.update(photons);
        return settings;
    };
    return {
        {"path", {{"integrator", "path"}, {"spp_per_pass", 4}}},
        {"path-sobol", {{"integrator", "path"}, {"spp_per_pass", 4}, {"sampler", "sobol"}}},
        {"path-sobol-16", {{"integrator", "path"}, {"spp_per_pass", 16}, {"sampler", "sobol"}}},
        // Adaptive sampling from the 8-pass pilot (32 spp) on.
        {"path-adaptive", {{"integrator", "path"}, {"spp_per_pass", 4}, {"adaptive", true}}},
        {"path-sobol-adaptive",
         {{"integrator", "path"}, {"spp_per_pass", 4}, {"sampler", "sobol"}, {"adaptive", true}}},
        // The preview preset's settings with sobol for its sobol_sequence (render/presets.cpp).
        {"path-sobol-8-adaptive",
         {{"integrator", "path"}, {"spp_per_pass", 8}, {"sampler", "sobol"}, {"adaptive", true}}},
        // Caustics from a progressive caustic photon map (caustics = photon_map): `photons`
        // caustic-only paths a pass, about one for every two to three camera samples.
        {"path-caustic-map",
         {{"integrator", "path"},
          {"spp_per_pass", 4},
          {"caustics", "photon_map"},
          {"photons", 15000}}},
        {"path-sobol-16-caustic-map",
         {{"integrator", "path"},
          {"spp_per_pass", 16},
          {"sampler", "sobol"},
          {"caustics", "photon_map"},
          {"photons", 50000}}},
        // One Sobol' sequence through a pixel's passes: faster convergence, and an error
        // estimate that overestimates (core/sampler.h).
        {"path-sobol-sequence-16",
         {{"integrator", "path"}, {"spp_per_pass", 16}, {"sampler", "sobol_sequence"}}},
        // The presets' settings: final's (above) and preview's.
        {"path-sobol-sequence-8-adaptive",
         {{"integrator", "path"},
          {"spp_per_pass", 8},
          {"sampler", "sobol_sequence"},
          {"adaptive", true}}},
        {"path-sobol-sequence-16-caustic-map",
         {{"integrator", "path"},
          {"spp_per_pass", 16},
          {"sampler", "sobol_sequence"},
          {"caustics", "photon_map"},
          {"photons", 50000}}},
        // Indirect light from a progressive photon map at the second diffuse vertex
        // (indirect = photon_map): with independent numbers, so that the bias table sees it; with
        // the final preset's sampler; and with both maps, as bench/mitsuba_compare.sh and
        // bench/cycles_compare.sh run the bunny and cornell-spheres.
        {"path-indirect-map",
         {{"integrator", "path"},
          {"spp_per_pass", 4},
          {"indirect", "photon_map"},
          {"indirect_photons", 10000}}},
        {"path-sobol-sequence-16-indirect-map",
         {{"integrator", "path"},
          {"spp_per_pass", 16},
          {"sampler", "sobol_sequence"},
          {"indirect", "photon_map"}}},
        {"path-sobol-sequence-16-photon-maps",
         {{"integrator", "path"},
          {"spp_per_pass", 16},
          {"sampler", "sobol_sequence"},
          {"caustics", "photon_map"},
          {"photons", 50000},
          {"indirect", "photon_map"}}},
        {"photon-k50", with({{"integrator", "photon"}, {"spp_per_pass", 4}, {"k", 50}})},
        {"photon-k200", with({{"integrator", "photon"}, {"spp_per_pass", 4}, {"k", 200}})},
        {"ppm", with({{"integrator", "ppm"}, {"spp_per_pass", 4}})},
        {"ppm-alpha-0.5", with({{"integrator", "ppm"}, {"spp_per_pass", 4}, {"alpha", 0.5}})},
    };
}

const std::vector<std::string> kScenes = {"cornell-box",   "cornell-spheres", "bunny",
                                          "caustic-glass", "meshes",          "indirect"};
// Scenes no setting was tuned on (glossy and rough materials, textures, an environment, spot
// lights): --trust runs them beside the study's.
const std::vector<std::string> kHeldOutScenes = {"outdoor-metals", "product-shot", "stage-lights"};

// Whether a configuration's estimator is biased (photon maps): its film has the bias layer.
bool biased(const Config& c) {
    const Json& s = c.settings;
    return s.value("integrator", "path") != "path" || s.value("caustics", "") == "photon_map" ||
           s.value("indirect", "") == "photon_map";
}

struct Options {
    std::vector<std::string> scenes = kScenes;
    std::vector<std::string> configs;  // names; empty for all
    int size = 96;
    int refSpp = 16384;
    std::vector<int> ladder = {4, 8, 16, 32, 64, 128, 256};
    std::vector<int> passLadder;  // rungs in passes instead of spp, when given
    int seeds = 1;
    std::string csv = "study.csv";
    double forecastTarget = 0.015;
};

int parseArgs(int argc, char** argv, Options& o) {
    CLI::App app("The speed/accuracy study: error against time for every scene and integrator.",
                 "bench_study");
    int repeatsUnused = 1;
    bool smoke = false;
    addCommonOptions(app, repeatsUnused, "Unused (see --seeds)", smoke,
                     "2 scenes at 24x24, a 1024-spp reference, rungs 4 to 32");
    std::vector<std::string> sceneNames = kScenes;
    sceneNames.insert(sceneNames.end(), kHeldOutScenes.begin(), kHeldOutScenes.end());
    app.add_option("--scenes", o.scenes, "Example scenes, comma-separated")
        ->delimiter(',')
        ->check(CLI::IsMember(sceneNames))
        ->capture_default_str();
    std::vector<std::string> names;
    for (const Config& c : allConfigs()) names.push_back(c.name);
    app.add_option("--configs", o.configs, "Configurations, comma-separated (default: all)")
        ->delimiter(',')
        ->check(CLI::IsMember(names));
    caustic::cli::addNumber(app, "--size", o.size, 1, 4096, "Square resolution");
    caustic::cli::addNumber(app, "--ref-spp", o.refSpp, 1, 1e7,
                            "Samples per pixel of the path-traced reference");
    caustic::cli::addNumber(app, "--ladder", o.ladder, 1, 1e6,
                            "Rungs, samples per pixel, comma-separated, increasing");
    caustic::cli::addNumber(app, "--passes", o.passLadder, 1, 1e6,
                            "Rungs in passes instead of spp, comma-separated, increasing");
    caustic::cli::addNumber(app, "--seeds", o.seeds, 1, 1000, "Renders per configuration");
    bool trust = false;
    app.add_flag("--trust", trust,
                 "The error estimate of the photon maps: every biased configuration on every "
                 "scene, the held-out ones too, at 8, 32 and 128 passes, 64x64, 2 seeds (options "
                 "after it override)");
    app.add_option("--csv", o.csv,
                   "Where the rows go; the forecasts go beside it, to NAME-forecast.csv")
        ->capture_default_str();
    caustic::cli::addNumber(app, "--forecast-target", o.forecastTarget, 1e-4, 1,
                            "Target error of the forecast's renders (path, 4 spp per pass)");
    if (int exitCode = parseBenchmarkArgs(app, argc, argv); exitCode >= 0) return exitCode;
    if (trust) {
        // Defaults of the trust run; options given after --trust still apply (CLI11 parsed them),
        // so only what was not given is set here.
        if (app.count("--scenes") == 0) {
            o.scenes = sceneNames;
        }
        if (app.count("--configs") == 0)
            for (const Config& c : allConfigs())
                if (biased(c)) o.configs.push_back(c.name);
        if (app.count("--passes") == 0) o.passLadder = {8, 32, 128};
        if (app.count("--size") == 0) o.size = 64;
        if (app.count("--seeds") == 0) o.seeds = 2;
        o.forecastTarget = 0;
    }
    if (smoke) {
        o.scenes = {"cornell-spheres", "caustic-glass"};
        o.size = 24;
        o.refSpp = 1024;
        o.ladder = {4, 8, 16, 32};
        o.forecastTarget = 0.05;
    }
    std::sort(o.ladder.begin(), o.ladder.end());
    std::sort(o.passLadder.begin(), o.passLadder.end());
    return -1;
}

// Named regions of a scene's image (one mask per pixel), from where each pixel's centre ray first
// hits. Every example is a box with walls at x = +-1, y = +-1 and z = -1.
struct Regions {
    std::vector<char> caustic;  // empty when the scene has no glass sphere
    std::vector<char> edges;    // within 0.1 of two walls: the room's edges and corners
    int causticPixels = 0, edgePixels = 0;
};

Vec3 vec3(const Json& j) {
    return Vec3(j[0].get<float>(), j[1].get<float>(), j[2].get<float>());
}

// The caustic: floor points within 0.45 radii of where the line from the light's centre through
// the glass sphere's centre meets the floor (bench_equal_time measured 95% of a Snell trace's
// floor hits within 0.39 radii on cornell-spheres); seen directly, not through the glass.
Regions regionsOf(const Json& doc, const caustic::Scene& scene) {
    std::optional<Vec3> glass, light;
    float glassRadius = 0;
    for (const Json& shape : doc["shapes"]) {
        const Json& m = doc["materials"][shape["material"].get<std::string>()];
        if (shape["type"] == "sphere" && m["type"] == "dielectric") {
            glass = vec3(shape["center"]);
            glassRadius = shape["radius"].get<float>();
        } else if (m.contains("emission")) {
            light = shape["type"] == "sphere"
                        ? vec3(shape["center"])
                        : vec3(shape["origin"]) + 0.5f * (vec3(shape["u"]) + vec3(shape["v"]));
        }
    }
    std::optional<Vec3> causticCentre;
    if (glass && light) {
        const Vec3 d = *glass - *light;
        causticCentre = *light + d * ((-1.0f - light->y) / d.y);
    }
    const caustic::Camera& camera = scene.camera;
    const Vec3 cameraPosition = vec3(doc["camera"]["position"]);
    auto accel = caustic::createAccelerator("embree", scene.geometry);
    Regions r;
    const size_t pixels = size_t(camera.width()) * size_t(camera.height());
    r.edges.assign(pixels, 0);
    if (causticCentre) r.caustic.assign(pixels, 0);
    for (int y = 0; y < camera.height(); ++y)
        for (int x = 0; x < camera.width(); ++x) {
            caustic::Ray ray = camera.generateRay(float(x) + 0.5f, float(y) + 0.5f);
            std::optional<caustic::Hit> hit = accel->intersect(ray, caustic::kInfinity);
            if (!hit) continue;
            const Vec3 p =
                cameraPosition + ray.o + hit->t * ray.d;  // the loader centres the camera
            const size_t i = size_t(y) * size_t(camera.width()) + size_t(x);
            const int near =
                int(1 - std::abs(p.x) < 0.1f) + int(1 - std::abs(p.y) < 0.1f) + int(p.z + 1 < 0.1f);
            if (near >= 2) r.edges[i] = 1, ++r.edgePixels;
            if (causticCentre && std::abs(p.y + 1) < 1e-3f &&
                std::hypot(p.x - causticCentre->x, p.z - causticCentre->z) < 0.45f * glassRadius)
                r.caustic[i] = 1, ++r.causticPixels;
        }
    return r;
}

// The reference of one scene: from the cache beside this binary, else rendered and saved.
Reference reference(const caustic::Scene& scene, const Json& doc, const Options& opt) {
    caustic::RenderSettings s;
    s.integrator = "path";
    s.spp = opt.refSpp;
    s.seed = 1000003;  // the measured renders use seeds 1, 2, ...
    return cachedReference(scene, doc, s,
                           std::filesystem::read_symlink("/proc/self/exe").parent_path() / "study",
                           CAUSTIC_RENDERER_LIBRARY);
}

// One rung's figures.
struct Rung {
    int spp = 0, passes = 0;
    double seconds = 0, rmse = 0, relMse = 0, rmseCaustic = -1, rmseEdges = 0, reported = 0,
           trueRelative = 0, noiseRelative = 0, biasRms = 0, coverage = 0, reportedNoise = 0,
           reportedBias = 0;
};

Rung measure(const caustic::Film& film, const Reference& ref, const Regions& regions) {
    const std::vector<float> mean = film.meanRgb(), se = film.standardErrorRgb(),
                             bias = film.biasRgb();
    const double t = film.passes() >= 2 ? caustic::studentThreshold(0.05, film.passes() - 1) : 0;
    Sums all, caustic, edges;
    double relSq = 0;
    size_t covered = 0;
    for (size_t i = 0; i < mean.size(); ++i) {
        all.add(mean[i], se[i], ref.mean[i], ref.se[i]);
        if (!regions.caustic.empty() && regions.caustic[i / 3])
            caustic.add(mean[i], se[i], ref.mean[i], ref.se[i]);
        if (regions.edges[i / 3]) edges.add(mean[i], se[i], ref.mean[i], ref.se[i]);
        const double d = double(mean[i]) - ref.mean[i];
        // Relative MSE with Rousselle et al.'s 0.01 keeping dark pixels from dominating.
        relSq += d * d / (double(ref.mean[i]) * ref.mean[i] + 0.01);
        // The 95% interval from the passes, widened by the reference's own noise and by the
        // film's estimate of its bias there (zero for an unbiased estimator).
        covered += std::abs(d) <=
                   t * std::hypot(double(se[i]), double(ref.se[i])) + std::abs(double(bias[i]));
    }
    Rung r;
    r.passes = film.passes();
    r.rmse = all.rmseLessReference();
    r.relMse = relSq / double(mean.size());
    if (caustic.n) r.rmseCaustic = caustic.rmseLessReference();
    r.rmseEdges = edges.n ? edges.rmseLessReference() : 0;
    r.reported = film.relativeError();
    r.reportedNoise = film.relativeNoise();
    r.reportedBias = film.relativeBias();
    r.trueRelative = all.relativeLessReference();
    r.noiseRelative = all.relativeNoise();
    r.biasRms = all.bias();
    r.coverage = double(covered) / double(mean.size());
    return r;
}

// The forecast of the time to a target error (render/forecast.h) after 8, 16 and 32 passes,
// against the time the render really took: one row per scene and forecast.
void forecastRows(const caustic::Scene& scene, const std::string& sceneName, double target,
                  std::ostream& csv) {
    Json settings = {{"integrator", "path"},
                     {"spp_per_pass", 4},
                     {"spp", 65536},
                     {"target_error", target},
                     {"seed", 1}};
    const caustic::RenderSettings s = caustic::parseSettings(settings);
    struct Forecast {
        int passes;
        double elapsed, predictedTotal;
    };
    std::vector<Forecast> forecasts;
    int lastPasses = 0;
    caustic::RenderCallbacks callbacks;
    callbacks.onProgress = [&](const caustic::RenderProgress& p) {
        // The first report with a new pass count comes right after that pass, with its forecast.
        if (p.passesDone == lastPasses) return;
        lastPasses = p.passesDone;
        if ((p.passesDone == 8 || p.passesDone == 16 || p.passesDone == 32) && p.etaSeconds >= 0)
            forecasts.push_back({p.passesDone, p.elapsedSeconds, p.elapsedSeconds + p.etaSeconds});
    };
    caustic::RenderResult r = caustic::render(scene, s, callbacks);
    for (const Forecast& f : forecasts)
        csv << sceneName << ',' << target << ',' << f.passes << ',' << fmt("%.4f", f.elapsed) << ','
            << fmt("%.4f", f.predictedTotal) << ',' << fmt("%.4f", r.stats.renderSeconds) << ','
            << r.stats.passes << ',' << caustic::toString(r.stats.stopReason) << '\n';
    std::cerr << "  forecast to " << target << ": " << r.stats.passes << " passes, "
              << fmt("%.2f", r.stats.renderSeconds) << " s\n";
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    if (int exitCode = parseArgs(argc, argv, opt); exitCode >= 0) return exitCode;
    try {
        std::ofstream csv(opt.csv);
        if (!csv) throw std::runtime_error("cannot write " + opt.csv);
        csv << "scene,config,integrator,sampler,spp_per_pass,seed,spp,passes,seconds,rmse,rel_mse,"
               "rmse_caustic,rmse_edges,reported_rel_error,true_rel_error,noise_rel_error,bias_rms,"
               "coverage95,reported_noise,reported_bias\n";
        Json meta = {{"reference_seconds", Json::object()}};
        std::ofstream forecastCsv(opt.csv.substr(0, opt.csv.rfind('.')) + "-forecast.csv");
        forecastCsv << "scene,target_error,after_passes,elapsed_seconds,predicted_seconds,"
                       "real_seconds,real_passes,stop_reason\n";
        for (const std::string& sceneName : opt.scenes) {
            Json doc = caustic::readJsonFile(std::string(CAUSTIC_DEFAULT_SCENES_DIR) + "/" +
                                             sceneName + ".json");
            doc["camera"]["width"] = opt.size;
            doc["camera"]["height"] = opt.size;
            auto scene = caustic::loadScene(doc, caustic::SceneOptions{CAUSTIC_DEFAULT_ASSETS_DIR});
            const Regions regions = regionsOf(doc, *scene);
            std::cerr << sceneName << ": " << regions.causticPixels << " caustic and "
                      << regions.edgePixels << " edge pixels\n";
            const Reference ref = reference(*scene, doc, opt);
            meta["reference_seconds"][sceneName] = ref.seconds;
            if (opt.forecastTarget > 0)
                forecastRows(*scene, sceneName, opt.forecastTarget, forecastCsv);
            for (const Config& config : allConfigs()) {
                if (!opt.configs.empty() && std::find(opt.configs.begin(), opt.configs.end(),
                                                      config.name) == opt.configs.end())
                    continue;
                for (int seed = 1; seed <= opt.seeds; ++seed) {
                    Json settings = config.settings;
                    settings["seed"] = seed;
                    const int perPass = caustic::parseSettings(settings).resolvedSppPerPass();
                    // Rungs in spp: the --passes ladder's, or --ladder's.
                    std::vector<int> ladder = opt.ladder;
                    if (!opt.passLadder.empty()) {
                        ladder.clear();
                        for (int passes : opt.passLadder) ladder.push_back(passes * perPass);
                    }
                    settings["spp"] = ladder.back();
                    const caustic::RenderSettings s = caustic::parseSettings(settings);
                    std::vector<Rung> rungs;
                    // The time spent measuring is not the render's.
                    double measuring = 0;
                    const auto start = std::chrono::steady_clock::now();
                    caustic::RenderCallbacks callbacks;
                    callbacks.onPass = [&](const caustic::Film& film) {
                        const int spp = film.passes() * perPass;
                        if (std::find(ladder.begin(), ladder.end(), spp) == ladder.end()) return;
                        const double elapsed = secondsSince(start) - measuring;
                        const auto t0 = std::chrono::steady_clock::now();
                        Rung r = measure(film, ref, regions);
                        r.spp = spp;
                        r.seconds = elapsed;
                        rungs.push_back(r);
                        measuring += secondsSince(t0);
                    };
                    caustic::render(*scene, s, callbacks);
                    const std::string sampler = s.toJson()["sampler"];
                    // The estimator: path with photon maps is biased (consistent).
                    const bool caustics = s.path.caustics == caustic::PathSource::PhotonMap;
                    const bool indirect = s.path.indirect == caustic::PathSource::PhotonMap;
                    const std::string integrator =
                        s.integrator != "path" ? s.integrator
                        : indirect ? (caustics ? "path+photon_maps" : "path+indirect_map")
                        : caustics ? "path+photon_map"
                                   : s.integrator;
                    for (const Rung& r : rungs)
                        csv << sceneName << ',' << config.name << ',' << integrator << ','
                            << sampler << ',' << perPass << ',' << seed << ',' << r.spp << ','
                            << r.passes << ',' << fmt("%.4f", r.seconds) << ','
                            << fmt("%.6g", r.rmse) << ',' << fmt("%.6g", r.relMse) << ','
                            << (r.rmseCaustic >= 0 ? fmt("%.6g", r.rmseCaustic) : "") << ','
                            << fmt("%.6g", r.rmseEdges) << ',' << fmt("%.6g", r.reported) << ','
                            << fmt("%.6g", r.trueRelative) << ',' << fmt("%.6g", r.noiseRelative)
                            << ',' << fmt("%.6g", r.biasRms) << ',' << fmt("%.4f", r.coverage)
                            << ',' << fmt("%.6g", r.reportedNoise) << ','
                            << fmt("%.6g", r.reportedBias) << '\n';
                    csv.flush();
                    std::cerr << "  " << config.name << " seed " << seed << ": " << rungs.size()
                              << " rungs, " << fmt("%.1f", rungs.empty() ? 0 : rungs.back().seconds)
                              << " s\n";
                }
            }
        }
        // What the report needs to say how the rows were made.
        meta["size"] = opt.size;
        meta["ref_spp"] = opt.refSpp;
        meta["ladder"] = opt.ladder;
        meta["pass_ladder"] = opt.passLadder;
        meta["seeds"] = opt.seeds;
        meta["forecast_target"] = opt.forecastTarget;
        meta["machine"] = "nproc " + std::to_string(onlineCpus()) + ", OpenMP threads " +
                          std::to_string(omp_get_max_threads()) + ", " + cpuModel() + ".";
        std::ofstream(opt.csv + ".json") << meta.dump(2) << "\n";
        std::cout << "wrote " << opt.csv << " and " << opt.csv << ".json\n";
    } catch (const std::exception& e) {
        std::cerr << "bench_study: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
