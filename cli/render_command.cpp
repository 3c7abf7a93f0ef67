#include "render_command.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "core/error.h"
#include "film/image_io.h"
#include "progress_bar.h"
#include "render/renderer.h"
#include "render/settings.h"
#include "scene/scene.h"

namespace caustic {
namespace {

namespace fs = std::filesystem;

constexpr const char* kUsage =
    "usage: caustic render SCENE -o OUT.png|OUT.exr [-o ...] [--set key=value ...]\n"
    "                      [--assets DIR] [--stats FILE] [--progress | --no-progress] [--quiet]\n"
    "  SCENE        a scene JSON file, or the name of an example scene (cornell-spheres)\n"
    "  -o FILE      output image; .png (sRGB, 8-bit) or .exr (linear float); repeatable\n"
    "  --set k=v    override a render setting (caustic settings lists them)\n"
    "  --assets DIR folder that mesh files are read from (default: $CAUSTIC_ASSETS or the\n"
    "               repository's assets/meshes)\n"
    "  --stats FILE write the settings and the render's stats (time per phase, rays, error,\n"
    "               memory by component) as JSON\n";

struct Options {
    std::string scene;
    std::vector<fs::path> outputs;
    Json overrides = Json::object();
    fs::path assets;
    fs::path stats;
    int progress = -1;  // -1: when stderr is a terminal
    bool quiet = false;
};

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

Options parseArgs(const std::vector<std::string>& args) {
    Options o;
    const char* env = std::getenv("CAUSTIC_ASSETS");
    o.assets = env && *env ? fs::path(env) : fs::path(CAUSTIC_DEFAULT_ASSETS_DIR);
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
            return args[++i];
        };
        if (a == "-o" || a == "--output") {
            o.outputs.emplace_back(value());
        } else if (a == "--set") {
            const std::string& kv = value();
            size_t eq = kv.find('=');
            if (eq == std::string::npos || eq == 0)
                throw UsageError("--set takes key=value, got \"" + kv + "\"");
            o.overrides[kv.substr(0, eq)] = parseSettingValue(kv.substr(eq + 1));
        } else if (a == "--assets") {
            o.assets = value();
        } else if (a == "--stats") {
            o.stats = value();
        } else if (a == "--progress") {
            o.progress = 1;
        } else if (a == "--no-progress") {
            o.progress = 0;
        } else if (a == "--quiet" || a == "-q") {
            o.quiet = true;
        } else if (!a.empty() && a[0] == '-') {
            throw UsageError("unknown option " + a);
        } else if (o.scene.empty()) {
            o.scene = a;
        } else {
            throw UsageError("more than one scene given (\"" + o.scene + "\", \"" + a + "\")");
        }
    }
    if (o.scene.empty()) throw UsageError("no scene given");
    if (o.outputs.empty()) throw UsageError("no output given (-o OUT.png or -o OUT.exr)");
    for (const fs::path& out : o.outputs) {
        std::string ext = out.extension().string();
        if (ext != ".png" && ext != ".exr")
            throw UsageError("output " + out.string() + " must end in .png or .exr");
    }
    return o;
}

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

}  // namespace

int runRenderCommand(const std::vector<std::string>& args) {
    if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
        std::cout << kUsage;
        return 0;
    }
    Options options;
    try {
        options = parseArgs(args);
    } catch (const UsageError& e) {
        std::cerr << "caustic: " << e.what() << "\n" << kUsage;
        return 2;
    }

    fs::path scenePath = resolveScene(options.scene);
    std::unique_ptr<Scene> scene;
    RenderSettings settings;
    try {
        SceneOptions sceneOptions;
        sceneOptions.assetsDir = options.assets;
        scene = loadScene(readJsonFile(scenePath), sceneOptions);
        settings = parseSettings(mergeSettings(scene->settings, options.overrides));
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
        for (const fs::path& out : options.outputs) writeImage(out, image, settings.exposure);
        if (!options.stats.empty()) writeStats(options.stats, settings, result.stats);
    } catch (const std::exception& e) {
        std::cerr << "caustic: error: " << e.what() << "\n";
        return 1;
    }

    if (!options.quiet) {
        const RenderStats& s = result.stats;
        char error[48] = "n/a (one pass)";
        if (std::isfinite(s.relativeError))
            std::snprintf(error, sizeof error, "%.3g%%", 100.0 * s.relativeError);
        std::string outs;
        for (const fs::path& out : options.outputs)
            outs += (outs.empty() ? "" : ", ") + out.string();
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
    }
    return 0;
}

}  // namespace caustic
