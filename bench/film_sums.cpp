// What exact pass sums cost (renderer/film/exact_sum.h): adding passes to the film and merging
// films, against plain double sums (sum += v, sumSq += v * v), on the same pass images, beside the
// time to render one such pass (cornell-spheres, path, 1 spp), so the cost is seen as a share of a
// render. Runs are interleaved; medians are reported.
#include <algorithm>
#include <iostream>
#include <random>
#include <vector>

#include "bench_common.h"
#include "film/film.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace {

using namespace caustic::bench;
using caustic::Color;

struct Options {
    int repeats = 5, size = 512, passes = 64;
};

// Parses the command line into `o`; returns -1 to run, else the exit code.
int parseArgs(int argc, char** argv, Options& o) {
    CLI::App app("What exact film sums cost against double sums.", "bench_film_sums");
    bool smoke = false;
    addCommonOptions(app, o.repeats, "Interleaved runs of each measurement", smoke,
                     "One run at 64x64 with 4 passes");
    caustic::cli::addNumber(app, "--size", o.size, 1, 16384, "Square image size");
    caustic::cli::addNumber(app, "--passes", o.passes, 1, 1e6, "Passes added per run");
    if (int exitCode = parseBenchmarkArgs(app, argc, argv); exitCode >= 0) return exitCode;
    if (smoke) o = Options{1, 64, 4};
    return -1;
}

// Pass images with a renderer's spread: most values 0.01-10, a few fireflies up to 1e6.
std::vector<std::vector<Color>> passImages(const Options& o) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<std::vector<Color>> out(size_t(o.passes));
    for (auto& pass : out) {
        pass.resize(size_t(o.size) * size_t(o.size));
        for (Color& c : pass)
            for (int k = 0; k < 3; ++k)
                c[k] = u(rng) < 0.01f ? std::pow(10.0f, 6.0f * u(rng)) : 10.0f * u(rng) * u(rng);
    }
    return out;
}

// The baseline exact sums are measured against: doubles, added in pass order.
void addDoubles(const std::vector<Color>& pass, std::vector<double>& sum,
                std::vector<double>& sumSq) {
    for (size_t p = 0; p < pass.size(); ++p)
        for (int c = 0; c < 3; ++c) {
            double v = pass[p][c];
            sum[3 * p + size_t(c)] += v;
            sumSq[3 * p + size_t(c)] += v * v;
        }
}

double renderPassSeconds(const Options& o) {
    nlohmann::json doc = caustic::readJsonFile(CAUSTIC_DEFAULT_SCENES_DIR "/cornell-spheres.json");
    doc["camera"]["width"] = o.size;
    doc["camera"]["height"] = o.size;
    auto scene = caustic::loadScene(doc, caustic::SceneOptions{});
    auto settings = caustic::parseSettings({{"integrator", "path"}, {"spp", 1}});
    return caustic::render(*scene, settings).stats.renderSeconds;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    if (int exitCode = parseArgs(argc, argv, o); exitCode >= 0) return exitCode;
    auto passes = passImages(o);
    const size_t n = size_t(o.size) * size_t(o.size) * 3;
    std::vector<double> exactAdd, doubleAdd, exactMerge, render;
    for (int r = 0; r < o.repeats; ++r) {
        caustic::Film film(o.size, o.size), half(o.size, o.size);
        auto t0 = std::chrono::steady_clock::now();
        for (int p = 0; p < o.passes; ++p) (p % 2 ? half : film).addPass(p, passes[size_t(p)]);
        exactAdd.push_back(secondsSince(t0));
        t0 = std::chrono::steady_clock::now();
        film.merge(half);
        exactMerge.push_back(secondsSince(t0));
        std::vector<double> sum(n, 0.0), sumSq(n, 0.0);
        t0 = std::chrono::steady_clock::now();
        for (const auto& pass : passes) addDoubles(pass, sum, sumSq);
        doubleAdd.push_back(secondsSince(t0));
        render.push_back(renderPassSeconds(o));
    }
    const double pixelPasses = double(o.size) * o.size * o.passes;
    const double exactNs = 1e9 * median(exactAdd) / pixelPasses;
    const double doubleNs = 1e9 * median(doubleAdd) / pixelPasses;
    const double renderNs = 1e9 * median(render) / (double(o.size) * o.size);
    std::cout << "Film sums at " << o.size << "x" << o.size << ", " << o.passes
              << " passes, median of " << o.repeats
              << " interleaved runs (exact sums added on every OpenMP thread, as a render does; "
                 "the double sums in one loop, as the film did):\n\n"
              << "| measurement | ns per pixel and pass | x double sums | share of a 1-spp path "
                 "pass |\n|---|---:|---:|---:|\n"
              << "| add a pass, double sums (before) | " << fmt("%.2f", doubleNs) << " | 1.00 | "
              << fmt("%.1f%%", 100 * doubleNs / renderNs) << " |\n"
              << "| add a pass, exact sums | " << fmt("%.2f", exactNs) << " | "
              << fmt("%.2f", exactNs / doubleNs) << " | " << fmt("%.1f%%", 100 * exactNs / renderNs)
              << " |\n"
              << "| merge two films, exact | "
              << fmt("%.2f", 1e9 * median(exactMerge) / (double(o.size) * o.size))
              << " per pixel | | |\n"
              << "| render one pass (cornell-spheres, path, 1 spp, every thread) | "
              << fmt("%.1f", renderNs) << " per pixel | | |\n";
    return 0;
}
