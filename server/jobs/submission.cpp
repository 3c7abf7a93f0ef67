#include "jobs/submission.h"

#include <algorithm>

#include "core/error.h"
#include "film/exact_sum.h"
#include "gltf/scene_document.h"
#include "render/integrator_factory.h"
#include "render/memory_estimate.h"
#include "render/presets.h"
#include "render/resolution.h"
#include "render/scene_traits.h"
#include "render/settings.h"
#include "scene/json_reader.h"
#include "scene/scene.h"

namespace caustic::server {
namespace fs = std::filesystem;

namespace {

std::string prefixed(const std::string& prefix, const std::string& path) {
    return path == "/" || path.empty() ? prefix : prefix + path;
}

std::string formatLimit(double v) {
    Json j = v;
    if (v == double(int64_t(v))) j = int64_t(v);
    return j.dump();
}

// The setting `spec` of `settings` held to the service's limit that caps it.
void atMost(const Json& settings, const SettingSpec& spec, const ServiceLimits& limits) {
    struct Cap {
        double limit;
        const char* what;
    };
    const Cap cap =
        spec.cap == SettingCap::Spp       ? Cap{double(limits.maxSpp), "samples per pixel"}
        : spec.cap == SettingCap::Photons ? Cap{double(limits.maxPhotons), "photon paths per pass"}
        : spec.cap == SettingCap::Seconds ? Cap{limits.maxTimeLimit, "seconds per render"}
                                          : Cap{limits.maxMemoryMiB, "MiB per render"};
    const double v = settings[spec.name].get<double>();
    if (v > cap.limit)
        throw InputError(jsonPointer("/settings", spec.name),
                         "must be at most " + formatLimit(cap.limit) + " on this server (" +
                             cap.what + "), got " + formatLimit(v));
}

Json resolveScene(const Json& scene, const ServerConfig& config, std::string& name) {
    if (!scene.is_string()) {
        if (!scene.is_object())
            throw InputError("/scene",
                             "expected a scene object or the name of an example scene, "
                             "got " +
                                 jsonTypeName(scene));
        return scene;
    }
    name = scene.get<std::string>();
    std::vector<std::string> names = exampleSceneNames(config.scenesDir);
    if (std::find(names.begin(), names.end(), name) == names.end()) {
        std::string valid;
        for (const std::string& n : names) valid += (valid.empty() ? "" : ", ") + n;
        throw InputError("/scene", "no example scene \"" + name + "\"; examples: " + valid);
    }
    return readJsonFile(config.scenesDir / (name + ".json"));
}

// An optional integer field of the body in [lo, hi]; `fallback` when absent.
// The pass images a target error's task holds and hands in (store/pass_images.h).
constexpr int64_t kMaxPassImageBytes = int64_t(256) << 20;

int64_t integerField(const Json& body, const char* name, int64_t lo, int64_t hi, int64_t fallback) {
    if (!body.contains(name)) return fallback;
    const Json& v = body[name];
    if (!v.is_number_integer() || v.get<int64_t>() < lo || v.get<int64_t>() > hi)
        throw InputError(jsonPointer("", name), "expected an integer in [" + std::to_string(lo) +
                                                    ", " + std::to_string(hi) + "], got " +
                                                    v.dump());
    return v.get<int64_t>();
}

}  // namespace

std::vector<std::string> exampleSceneNames(const fs::path& scenesDir) {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(scenesDir, ec))
        if (entry.is_regular_file() && entry.path().extension() == ".json")
            names.push_back(entry.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

Job prepareJob(const Json& body, const ServerConfig& config) {
    MeshCountCache uncached;
    return prepareJob(body, config, uncached);
}

Job prepareJob(const Json& body, const ServerConfig& config, MeshCountCache& meshCounts,
               const MeshAssetResolver& assets) {
    if (!body.is_object()) throw InputError("/", "expected an object, got " + jsonTypeName(body));
    for (auto it = body.begin(); it != body.end(); ++it)
        if (it.key() != "scene" && it.key() != "settings" && it.key() != "priority" &&
            it.key() != "task_passes")
            throw InputError(jsonPointer("", it.key()),
                             "unknown field; a job has \"scene\", \"settings\", \"priority\" "
                             "and \"task_passes\"");
    if (!body.contains("scene"))
        throw InputError("/scene", "required: a scene object or the name of an example scene");
    const ServiceLimits& limits = config.limits;

    Job job;
    job.scene = resolveScene(body["scene"], config, job.sceneName);
    SceneOptions options;
    options.assetsDir = config.assetsDir;
    options.maxResolution = limits.maxResolution;
    options.maxPixels = limits.maxPixels;
    options.countMeshesOnly = true;
    options.meshCounts = &meshCounts;
    if (assets)
        options.resolveMeshAsset = [&assets, &job](const std::string& id, const std::string& path,
                                                   bool needBytes) {
            MeshAsset asset = assets(id, path, needBytes);
            if (std::find(job.assets.begin(), job.assets.end(), id) == job.assets.end())
                job.assets.push_back(id);
            return asset;
        };
    std::unique_ptr<Scene> scene;
    Json model;
    try {
        if (isModelDocument(job.scene) && job.scene["gltf"].is_object() &&
            job.scene["gltf"].contains("summary"))
            throw InputError("/gltf/summary", "is written by the service, not by a request");
        scene = loadSceneDocument(job.scene, options, &model);
    } catch (const InputError& e) {
        throw InputError(prefixed("/scene", e.path()), e.message());
    }
    // What the model holds and what was made of it (camera, environment, warnings), in the job.
    if (!model.is_null()) job.scene["gltf"]["summary"] = model;

    // The scene's settings, checked where they are, then the request's over them.
    parseSettings(scene->settings, "/scene/settings");
    Json asked = body.value("settings", Json::object());
    if (!asked.is_object())
        throw InputError("/settings", "expected an object, got " + jsonTypeName(asked));
    const SceneTraits traits = sceneTraits(*scene);
    Json merged = mergeSettings(scene->settings, asked, &traits);
    job.presetChoice = presetChoice(merged, traits);
    // The settings as admitted: the service's limits on every setting the job's integrator reads
    // that one caps (a path job's photons only with a photon map: without one it traces none),
    // its defaults for the time and memory limits, and the memory estimate.
    auto admit = [&](const Json& values) {
        RenderSettings settings = parseSettings(values, "/settings");
        applyResolution(*scene, settings, options);
        const Json s = settings.toJson();
        for (const SettingSpec& spec : settingSpecs())
            if (spec.cap != SettingCap::None && s.contains(spec.name)) atMost(s, spec, limits);
        if (settings.timeLimit == 0) settings.timeLimit = limits.maxTimeLimit;
        if (settings.memoryLimit == 0) settings.memoryLimit = limits.maxMemoryMiB;
        if (config.renderThreads > 0 &&
            (settings.threads == 0 || settings.threads > config.renderThreads))
            settings.threads = config.renderThreads;
        checkMemoryEstimate(*scene, settings);
        return settings;
    };
    RenderSettings settings;
    try {
        settings = admit(merged);
    } catch (const InputError& e) {
        // Photon maps the preset chose, where this service's limits leave no room for them, are
        // left out (the reasons say so): the job is refused only for what its request asked.
        // A map the request or the scene asked for stays, and is refused.
        if (job.presetChoice.is_null()) throw;
        Json kept = Json::object();
        bool dropped = false;
        for (auto& [key, value] : job.presetChoice["settings"].items()) {
            if (asked.contains(key) || scene->settings.contains(key)) {
                kept[key] = value;
                continue;
            }
            merged[key] = "paths";
            dropped = true;
            job.presetChoice["reasons"].push_back(key + ": paths after all; " + e.path() + ": " +
                                                  e.message());
        }
        if (!dropped) throw;
        job.presetChoice["settings"] = kept;
        settings = admit(merged);
    }

    job.settings = settings.toJson();
    job.priority = int(integerField(body, "priority", -1000, 1000, 0));
    // Split into tasks where workers share a store (store/task.h).
    const int64_t taskPasses = integerField(body, "task_passes", 1, exact::kMaxPasses, 0);
    if (!config.store.empty()) {
        job.passesTotal = settings.passesTotal();
        job.taskPasses = int(taskPasses > 0 ? taskPasses : config.taskPasses);
        if (settings.targetError > 0) {
            // A target error's task hands in each pass's image (12 bytes a pixel, 24 with its
            // bias), held in its worker's memory until then: at most kMaxPassImageBytes a task.
            const int64_t pixels = int64_t(scene->camera.width()) * scene->camera.height();
            const int64_t bytes =
                estimatesBias(settings.integrator, settings.path.photonMapped()) ? 24 : 12;
            const auto most = int(std::max<int64_t>(1, kMaxPassImageBytes / (bytes * pixels)));
            if (taskPasses > most)
                throw InputError("/task_passes",
                                 "a job with a target error hands in each pass's image: at " +
                                     std::to_string(scene->camera.width()) + "x" +
                                     std::to_string(scene->camera.height()) + ", at most " +
                                     std::to_string(most) + " passes a task (256 MiB), got " +
                                     std::to_string(taskPasses));
            job.taskPasses = std::min(job.taskPasses, most);
        }
    }
    return job;
}

}  // namespace caustic::server
