// Recreates the seed report's Table 1: photon mapping render time with the photon kd-tree and
// without it (brute force: every photon for every look-up), at several photon counts, with the same
// image settings. Renders alternate (kd-tree, brute force, kd-tree, ...) because the machine is
// shared and noisy; the ratios are reported beside the seed's published figures.
#include <omp.h>

#include "bench_common.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "accel/accelerator.h"
#include "photons/photon_tracer.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace {

using namespace caustic::bench;

// The seed report's Table 1 (shared/seed/report-zh.txt): seconds per image, 16 spp, k = 50.
struct SeedRow {
    int64_t photons;
    double kdtree, brute;
};
constexpr SeedRow kSeed[] = {
    {10000, 20.22, 83.57}, {100000, 36.65, 635.27}, {1000000, 85.65, 7594.54}};

std::optional<SeedRow> seedRow(int64_t photons) {
    for (const SeedRow& r : kSeed)
        if (r.photons == photons) return r;
    return std::nullopt;
}

struct Options {
    int size = 64;
    int spp = 16;
    int repeats = 3;       // kd-tree renders per photon count
    int bruteRepeats = 1;  // brute-force renders per photon count
    std::vector<int64_t> photons = {10000, 100000, 1000000};
};

// Parses the command line into `o`; returns -1 to run, else the exit code.
int parseArgs(int argc, char** argv, Options& o) {
    CLI::App app("Photon mapping with kd-tree and brute-force look-ups (the seed's Table 1).",
                 "bench_photon_table1");
    bool smoke = false;
    addCommonOptions(app, o.repeats, "kd-tree renders per photon count; the median is kept", smoke,
                     "16x16, 2 spp, photons 1000,10000, one render each");
    caustic::cli::addNumber(app, "--size", o.size, 1, 16384, "Square resolution");
    caustic::cli::addNumber(app, "--photons", o.photons, 1, 1e9,
                            "Photon paths traced, comma-separated; 1e5 or 100000");
    caustic::cli::addNumber(app, "--brute-repeats", o.bruteRepeats, 1, 1e6,
                            "Brute-force renders per photon count");
    if (int exitCode = parseBenchmarkArgs(app, argc, argv); exitCode >= 0) return exitCode;
    if (smoke) {
        o.size = 16;
        o.spp = 2;
        o.repeats = 1;
        o.bruteRepeats = 1;
        o.photons = {1000, 10000};
    }
    return -1;
}

std::string loadAverage() {
    std::ifstream in("/proc/loadavg");
    std::string a, b, c;
    in >> a >> b >> c;
    return a + " " + b + " " + c;
}

// The renders of one look-up at one photon count.
struct Runs {
    std::vector<double> passSetup, lookups, total;  // seconds
    bool sameImage = true;                          // every image equals the reference

    void add(const caustic::RenderResult& r, std::vector<float>& reference) {
        const caustic::RenderStats& s = r.stats;
        passSetup.push_back(s.passSetupSeconds);
        lookups.push_back(s.renderSeconds - s.passSetupSeconds);
        total.push_back(s.totalSeconds);
        std::vector<float> image = r.film->meanRgb();
        if (reference.empty()) reference = image;
        sameImage = sameImage && image == reference;
    }
};

struct CountResult {
    int64_t photons;
    size_t global = 0, caustic = 0;  // photons stored in each map
    Runs kdtree, brute;
};

// The photons the integrator stores in its one pass: the same tracing, outside the timings.
void countStored(const caustic::Scene& scene, const caustic::RenderSettings& settings,
                 CountResult& r) {
    auto accel = caustic::createAccelerator(settings.accelerator, scene.geometry);
    caustic::PhotonTracingOptions o;
    o.photons = uint64_t(r.photons);
    o.maxDepth = settings.maxDepth;
    o.seed = settings.seed;
    const caustic::PhotonTracing t = caustic::tracePhotons(scene, *accel, o);
    r.global = t.photons.size();
    r.caustic = size_t(std::count_if(t.photons.begin(), t.photons.end(), [](const auto& p) {
        return p.path == caustic::PhotonPath::Caustic;
    }));
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    if (int exitCode = parseArgs(argc, argv, opt); exitCode >= 0) return exitCode;
    const int threads = omp_get_max_threads();
    const std::string loadBefore = loadAverage();

    caustic::RenderSettings settings;
    settings.integrator = "photon";
    settings.spp = opt.spp;
    settings.sppPerPass = opt.spp;  // one pass: one photon tracing, one pair of maps
    settings.photon.k = 50;
    settings.seed = 0;
    settings.threads = threads;

    std::vector<CountResult> results;
    try {
        nlohmann::json doc = caustic::readJsonFile(std::string(CAUSTIC_DEFAULT_SCENES_DIR) +
                                                   "/cornell-spheres.json");
        doc["camera"]["width"] = opt.size;
        doc["camera"]["height"] = opt.size;
        auto scene = caustic::loadScene(doc, caustic::SceneOptions{CAUSTIC_DEFAULT_ASSETS_DIR});

        // One untimed warm-up (page faults, OpenMP thread pool).
        settings.photon.photons = uint64_t(opt.photons.front());
        settings.photon.lookup = caustic::PhotonLookup::KdTree;
        caustic::render(*scene, settings);

        for (int64_t photons : opt.photons) {
            CountResult r{photons, 0, 0, {}, {}};
            countStored(*scene, settings, r);
            settings.photon.photons = uint64_t(photons);
            // Interleave kd-tree and brute force; the kd-tree's remaining renders come last.
            std::vector<float> reference;
            for (int rep = 0; rep < std::max(opt.repeats, opt.bruteRepeats); ++rep) {
                if (rep < opt.repeats) {
                    settings.photon.lookup = caustic::PhotonLookup::KdTree;
                    r.kdtree.add(caustic::render(*scene, settings), reference);
                }
                if (rep < opt.bruteRepeats) {
                    settings.photon.lookup = caustic::PhotonLookup::BruteForce;
                    r.brute.add(caustic::render(*scene, settings), reference);
                }
            }
            results.push_back(std::move(r));
            std::cerr << "done " << photons << " photons\n";
        }
    } catch (const std::exception& e) {
        std::cerr << "bench_photon_table1: " << e.what() << "\n";
        return 1;
    }

    // Table 1 beside the seed's: total seconds per image.
    const std::string size = std::to_string(opt.size);
    std::cout << "### Photon mapping, cornell-spheres, " << size << "x" << size << ", " << opt.spp
              << " spp in one pass, k = 50, " << threads << " threads: seconds per image, "
              << "kd-tree (median of " << opt.repeats << ") against brute force (median of "
              << opt.bruteRepeats << ")\n\n"
              << "| photon paths | photons stored (global + caustic map) | seed kd-tree | seed "
              << "brute force | seed brute / kd | kd-tree total | brute force total | brute / kd "
              << "(total) | brute / kd (render phase) | same image |\n"
              << "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
    bool same = true;
    for (const CountResult& r : results) {
        const std::optional<SeedRow> seed = seedRow(r.photons);
        const bool sameImage = r.kdtree.sameImage && r.brute.sameImage;
        same = same && sameImage;
        std::cout << "| " << r.photons << " | " << r.global << " + " << r.caustic << " | "
                  << (seed ? fmt("%.2f", seed->kdtree) : "—") << " | "
                  << (seed ? fmt("%.2f", seed->brute) : "—") << " | "
                  << (seed ? fmt("%.1f×", seed->brute / seed->kdtree) : "—") << " | "
                  << fmt("%.3f", median(r.kdtree.total)) << " | "
                  << fmt("%.3f", median(r.brute.total)) << " | "
                  << fmt("%.1f×", median(r.brute.total) / median(r.kdtree.total)) << " | "
                  << fmt("%.1f×", median(r.brute.lookups) / median(r.kdtree.lookups)) << " | "
                  << (sameImage ? "yes" : "**no**") << " |\n";
    }

    // The phases behind each total.
    const double samples = double(opt.size) * double(opt.size) * double(opt.spp);
    std::cout
        << "\n### Detail (medians): the render phase is the camera paths and their "
        << "look-ups, two per path (caustic map, global map)\n\n"
        << "| photon paths | look-up | renders | photon tracing + map build s | render phase s "
        << "| total s | render phase, thread-µs per camera sample |\n"
        << "|---:|---|---:|---:|---:|---:|---:|\n";
    for (const CountResult& r : results)
        for (const Runs* runs : {&r.kdtree, &r.brute}) {
            const double lookups = median(runs->lookups);
            std::cout << "| " << r.photons << " | "
                      << (runs == &r.kdtree ? "kd-tree" : "brute force") << " | "
                      << runs->total.size() << " | " << fmt("%.3f", median(runs->passSetup))
                      << " | " << fmt("%.3f", lookups) << " | " << fmt("%.3f", median(runs->total))
                      << " | " << fmt("%.2f", 1e6 * lookups * threads / samples) << " |\n";
        }
    std::cout << "\nSeed: its own framework and machine, resolution unreported, 16 spp, k = 50; "
                 "compare its ratios with ours, not its seconds. Photon paths are paths emitted; "
                 "total includes the accelerator build and the integrator's setup.\n\n"
              << "Load average before: " << loadBefore << "; after: " << loadAverage() << ".\n";
    if (!same) std::cerr << "bench_photon_table1: kd-tree and brute-force images differ\n";
    return same ? 0 : 1;
}
