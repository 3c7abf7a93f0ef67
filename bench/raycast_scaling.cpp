// Recreates the seed report's Table 2: ray casting (1 sample per pixel) of cornell-spheres at
// several square resolutions, with 1 thread and with every OpenMP thread. Runs are interleaved (1,
// all, 1, all, ...) because the machine is shared and noisy; medians, mins and ratios are reported
// beside the seed's published figures.
#include <omp.h>

#include <sched.h>
#include "bench_common.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "accel/accelerator.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace {

using namespace caustic::bench;

using caustic::RenderStats;

// The seed report's Table 2 (shared/seed/report-zh.txt): seconds per ray-cast image.
struct SeedRow {
    int size;
    double openmp, serial;
};
constexpr SeedRow kSeed[] = {{500, 0.0435, 0.1428}, {1000, 0.1321, 0.6136}, {1500, 0.2949, 1.2940}};

std::optional<SeedRow> seedRow(int size) {
    for (const SeedRow& r : kSeed)
        if (r.size == size) return r;
    return std::nullopt;
}

// The fastest accelerator this build has: embree, else kdtree, else bruteforce.
std::string defaultAccelerator() {
    const std::vector<std::string>& names = caustic::acceleratorNames();
    for (const char* preferred : {"embree", "kdtree"})
        if (std::find(names.begin(), names.end(), preferred) != names.end()) return preferred;
    return "bruteforce";
}

struct Options {
    int repeats = 5;
    std::string accelerator = defaultAccelerator();
    std::vector<int> sizes = {500, 1000, 1500};
};

// Parses the command line into `o`; returns -1 to run, else the exit code.
int parseArgs(int argc, char** argv, Options& o) {
    CLI::App app("Ray casting time at 1 thread and at all threads (the seed's Table 2).",
                 "bench_raycast_scaling");
    bool smoke = false;
    addCommonOptions(app, o.repeats, "Interleaved 1-thread / all-thread pairs per size", smoke,
                     "One repeat at 64x64");
    app.add_option("--accelerator", o.accelerator,
                   "What is built (default: embree, else kdtree, else bruteforce)")
        ->check(CLI::IsMember(caustic::acceleratorNames()))
        ->capture_default_str();
    caustic::cli::addNumber(app, "--sizes", o.sizes, 1, 16384,
                            "Square resolutions, comma-separated");
    if (int exitCode = parseBenchmarkArgs(app, argc, argv); exitCode >= 0) return exitCode;
    if (smoke) {
        o.repeats = 1;
        o.sizes = {64};
    }
    return -1;
}

double minimum(const std::vector<double>& v) {
    return *std::min_element(v.begin(), v.end());
}

// The runs of one configuration (a size and a thread count).
struct Runs {
    std::vector<double> render, setup, total, raysPerSecond;
    uint64_t rays = 0;
    std::vector<double> firstSums;  // Film accumulators of the first run, to compare images.

    void add(const caustic::RenderResult& r) {
        if (render.empty()) firstSums = r.film->sums();
        render.push_back(r.stats.renderSeconds);
        setup.push_back(r.stats.setupSeconds);
        total.push_back(r.stats.totalSeconds);
        raysPerSecond.push_back(r.stats.raysPerSecond);
        rays = r.stats.rays;
    }
};

struct SizeResult {
    int size;
    Runs serial, parallel;
};

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    if (int exitCode = parseArgs(argc, argv, opt); exitCode >= 0) return exitCode;
    const int allThreads = omp_get_max_threads();

    std::vector<SizeResult> results;
    try {
        nlohmann::json doc = caustic::readJsonFile(std::string(CAUSTIC_DEFAULT_SCENES_DIR) +
                                                   "/cornell-spheres.json");
        for (int size : opt.sizes) {
            // Set the resolution in the scene JSON, then load.
            doc["camera"]["width"] = size;
            doc["camera"]["height"] = size;
            auto scene = caustic::loadScene(doc, caustic::SceneOptions{CAUSTIC_DEFAULT_ASSETS_DIR});
            caustic::RenderSettings settings;
            settings.integrator = "raycast";
            settings.spp = 1;
            settings.accelerator = opt.accelerator;
            settings.seed = 0;

            // One untimed warm-up (page faults, OpenMP thread pool), then interleave 1 / all.
            settings.threads = allThreads;
            caustic::render(*scene, settings);
            SizeResult r{size, {}, {}};
            for (int rep = 0; rep < opt.repeats; ++rep) {
                settings.threads = 1;
                r.serial.add(caustic::render(*scene, settings));
                settings.threads = allThreads;
                r.parallel.add(caustic::render(*scene, settings));
            }
            results.push_back(std::move(r));
            std::cerr << "done " << size << "x" << size << "\n";
        }
    } catch (const std::exception& e) {
        std::cerr << "bench_raycast_scaling: " << e.what() << "\n";
        return 1;
    }

    // Table 2 beside the seed's: render phase only.
    const std::string all = std::to_string(allThreads) + " threads";
    std::cout << "### Ray casting, 1 spp, cornell-spheres, accelerator " << opt.accelerator
              << ": render time (s), median of " << opt.repeats << " interleaved runs\n\n"
              << "| size | seed serial | seed OpenMP | seed speedup | 1 thread | " << all
              << " | speedup (medians) | 1 thread min | " << all
              << " min | speedup (mins) | same image |\n"
              << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
    for (const SizeResult& r : results) {
        std::optional<SeedRow> seed = seedRow(r.size);
        double s1 = median(r.serial.render), sN = median(r.parallel.render);
        double m1 = minimum(r.serial.render), mN = minimum(r.parallel.render);
        std::cout << "| " << r.size << "² | " << (seed ? fmt("%.4f", seed->serial) : "—") << " | "
                  << (seed ? fmt("%.4f", seed->openmp) : "—") << " | "
                  << (seed ? fmt("%.2f×", seed->serial / seed->openmp) : "—") << " | "
                  << fmt("%.4f", s1) << " | " << fmt("%.4f", sN) << " | " << fmt("%.2f×", s1 / sN)
                  << " | " << fmt("%.4f", m1) << " | " << fmt("%.4f", mN) << " | "
                  << fmt("%.2f×", m1 / mN) << " | "
                  << (r.serial.firstSums == r.parallel.firstSums ? "yes" : "**no**") << " |\n";
    }

    // Cost per configuration: setup included, and throughput.
    std::cout
        << "\n### Detail (medians): total includes setup (accelerator and integrator build)\n\n"
        << "| size | threads | rays per image | render s | total s | setup s | Mrays/s |\n"
        << "|---|---:|---:|---:|---:|---:|---:|\n";
    for (const SizeResult& r : results) {
        for (const Runs* runs : {&r.serial, &r.parallel}) {
            double render = median(runs->render), total = median(runs->total);
            std::cout << "| " << r.size << "² | " << (runs == &r.serial ? 1 : allThreads) << " | "
                      << runs->rays << " | " << fmt("%.4f", render) << " | " << fmt("%.4f", total)
                      << " | " << fmt("%.5f", median(runs->setup)) << " | "
                      << fmt("%.2f", median(runs->raysPerSecond) / 1e6) << " |\n";
        }
    }
    std::cout << "\nSeed: its own framework and machine (thread count unreported); compare ratios, "
                 "not seconds.\n";
    return 0;
}
