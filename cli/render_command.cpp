#include "render_command.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "core/error.h"
#include "film/image_io.h"
#include "gltf/scene_document.h"
#include "progress_bar.h"
#include "render/integrator_factory.h"
#include "render/presets.h"
#include "render/renderer.h"
#include "render/resolution.h"
#include "render/scene_traits.h"
#include "render/settings.h"
#include "scene/scene.h"

namespace caustic {
namespace {

namespace fs = std::filesystem;

// A scene argument names a file, or an example scene by name.
fs::path resolveScene(const std::string& arg) {
    fs::path p(arg);
    if (fs::exists(p)) return p;
    fs::path example = fs::path(CAUSTIC_DEFAULT_SCENES_DIR) / (arg + ".json");
    if (p.parent_path().empty() && p.extension().empty() && fs::exists(example)) return example;
    return p;
}

std::string formatRate(double perSecond) {
    char buf[32];
    if (perSecond >= 1e6)
        std::snprintf(buf, sizeof buf, "%.2f M", perSecond / 1e6);
    else
        std::snprintf(buf, sizeof buf, "%.0f ", perSecond);
    return buf;
}

// Writes {"settings", "stats"} as JSON, through a temporary file renamed into place.
void writeStats(const fs::path& file, const RenderSettings& settings, const RenderStats& stats) {
    fs::path tmp = file;
    tmp += ".tmp";
    {
        std::ofstream out(tmp);
        out << Json{{"settings", settings.toJson()}, {"stats", stats.toJson()}}.dump(2) << "\n";
        if (!out.flush()) throw std::runtime_error("cannot write " + file.string());
    }
    fs::rename(tmp, file);
}

// A glTF model as a scene, with the command line's overrides; its warnings and what it holds are
// printed unless quiet.
std::unique_ptr<Scene> loadGltfScene(const fs::path& file, const RenderOptions& options,
                                     const SceneOptions& sceneOptions) {
    const std::string name = file.filename().string(), path;
    const MeshErrors errors{name, path};
    Json s;
    std::unique_ptr<Scene> scene =
        loadModelScene(loadGltfPath(file, errors), options.gltf, sceneOptions, errors, &s);
    if (!options.quiet) {
        for (const Json& w : s["warnings"])
            std::cerr << "caustic: warning: " << name << ": " << w.get<std::string>() << "\n";
        std::cerr << "caustic: " << name << ": " << s["triangles"] << " triangles in " << s["draws"]
                  << " draws, " << scene->materials.size() << " materials, " << s["textures"].size()
                  << " textures, " << s["lights"].size() << " lights; camera " << s["camera"].dump()
                  << ", environment " << s["environment"].dump() << "\n";
    }
    return scene;
}

}  // namespace

int runRender(const RenderOptions& options) {
    fs::path scenePath = resolveScene(options.scene);
    std::unique_ptr<Scene> scene;
    RenderSettings settings;
    try {
        SceneOptions sceneOptions;
        sceneOptions.assetsDir = fs::path(options.assets);
        if (isGltfFileName(scenePath.string())) {
            scene = loadGltfScene(scenePath, options, sceneOptions);
        } else {
            if (!options.gltf.empty())
                throw InputError("", "--camera and --environment apply to glTF files only");
            scene = loadSceneDocument(readJsonFile(scenePath), sceneOptions);
        }
        const SceneTraits traits = sceneTraits(*scene);
        const Json merged = mergeSettings(scene->settings, options.overrides, &traits);
        settings = parseSettings(merged);
        applyResolution(*scene, settings, sceneOptions);
        // What a preset chose for this scene, and why.
        if (const Json choice = presetChoice(merged, traits); !choice.is_null() && !options.quiet)
            for (const Json& reason : choice["reasons"])
                std::cerr << "caustic: " << choice["preset"].get<std::string>() << ": "
                          << reason.get<std::string>() << "\n";
    } catch (const InputError& e) {
        std::cerr << "caustic: error: " << scenePath.string() << ": " << e.what() << "\n";
        return 2;
    }

    bool showProgress = options.progress == 1 || (options.progress == -1 && isatty(STDERR_FILENO));
    ProgressBar bar;
    RenderCallbacks callbacks;
    if (showProgress && !options.quiet)
        callbacks.onProgress = [&](const RenderProgress& p) { bar.update(p); };

    RenderResult result;
    try {
        result = render(*scene, settings, callbacks);
    } catch (const InputError& e) {
        bar.finish();
        std::cerr << "caustic: error: " << scenePath.string() << ": " << e.what() << "\n";
        return 2;
    }
    bar.finish();

    RgbImage image{result.film->width(), result.film->height(), result.film->meanRgb()};
    try {
        for (const std::string& out : options.outputs) writeImage(out, image, settings.exposure);
        if (!options.stats.empty()) writeStats(options.stats, settings, result.stats);
    } catch (const std::exception& e) {
        std::cerr << "caustic: error: " << e.what() << "\n";
        return 1;
    }

    if (!options.quiet) {
        const RenderStats& s = result.stats;
        char error[96] = "n/a (one pass)";
        if (std::isfinite(s.relativeError) && result.film->tracksBias())
            std::snprintf(error, sizeof error, "%.3g%% (noise %.3g%%, bias %.3g%%)",
                          100.0 * s.relativeError, 100.0 * s.relativeNoise, 100.0 * s.relativeBias);
        else if (std::isfinite(s.relativeError))
            std::snprintf(error, sizeof error, "%.3g%%", 100.0 * s.relativeError);
        std::string outs;
        for (const std::string& out : options.outputs) outs += (outs.empty() ? "" : ", ") + out;
        std::fprintf(stderr,
                     "caustic: %s: %s, %dx%d, %d spp in %d passes, %.3f s (setup %.3f s), "
                     "%srays/s on %d threads, relative error %s, stopped by %s, %llu samples "
                     "dropped, %.1f MB; wrote %s\n",
                     scenePath.filename().c_str(), settings.integrator.c_str(), image.width,
                     image.height, s.sppReached, s.passes, s.totalSeconds, s.setupSeconds,
                     formatRate(s.raysPerSecond).c_str(), s.threads, error,
                     toString(s.stopReason).c_str(),
                     static_cast<unsigned long long>(s.droppedSamples),
                     double(s.memory.total()) / 1e6, outs.c_str());
        // What the scene's features built, so that their cost is seen (none for a scene
        // without an environment image, textures or lights).
        std::string built;
        for (const BuiltPart& p : s.built) {
            char part[160];
            const bool small = p.bytes < 1000000;
            std::snprintf(part, sizeof part, "%s%s x%d %.3f s %.1f %s", built.empty() ? "" : ", ",
                          p.part.c_str(), p.count, p.seconds, double(p.bytes) / (small ? 1e3 : 1e6),
                          small ? "kB" : "MB");
            built += part;
        }
        if (!built.empty())
            std::fprintf(stderr, "caustic: built for the scene: %s\n", built.c_str());
    }
    return 0;
}

}  // namespace caustic
