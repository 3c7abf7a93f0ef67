// What exact pass sums cost (renderer/film/exact_sum.h): adding passes to the film and merging
// films, against the double sums the film kept before (sum += v, sumSq += v * v), on the same pass
// images, beside the time to render one such pass (cornell-spheres, path, 1 spp), so the cost is
// seen as a share of a render. Runs are interleaved; medians are reported.
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

constexpr const char* kUsage =
    "usage: bench_film_sums [--repeats N] [--size N] [--passes N] [--smoke]\n"
    "  --repeats N  interleaved runs of each measurement (default 5)\n"
    "  --size N     square image size (default 512)\n"
    "  --passes N   passes added per run (default 64)\n"
    "  --smoke      one run at 64x64 with 4 passes: checks that the benchmark runs\n";

struct Options {
    int repeats = 5, size = 512, passes = 64;
    bool smoke = false;
};

Options parse(const std::vector<std::string>& args) {
    Options o;
    forEachOption(args, o.repeats, o.smoke, [&](const std::string& a, auto value) {
        if (a == "--size")
            o.size = parsePositive(value(), a);
        else if (a == "--passes")
            o.passes = parsePositive(value(), a);
        else
            return false;
        return true;
    });
    if (o.smoke) o = Options{1, 64, 4, true};
    return o;
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

// The film's accumulation before exact sums: doubles, added in pass order.
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
    int exitCode = 0;
    std::optional<Options> options =
        startBenchmark("bench_film_sums", kUsage, argc, argv, parse, exitCode);
    if (!options) return exitCode;
    const Options& o = *options;
    auto passes = passImages(o);
    const size_t n = size_t(o.size) * size_t(o.size) * 3;
    std::vector<double> exactAdd, doubleAdd, exactMerge, render;
    for (int r = 0; r < o.repeats; ++r) {
        auto t0 = std::chrono::steady_clock::now();
        caustic::Film film(o.size, o.size), half(o.size, o.size);
        for (int p = 0; p < o.passes; ++p) (p % 2 ? half : film).addPass(p, passes[size_t(p)]);
        exactAdd.push_back(secondsSince(t0));
        t0 = std::chrono::steady_clock::now();
        film.merge(half);
        exactMerge.push_back(secondsSince(t0));
        t0 = std::chrono::steady_clock::now();
        std::vector<double> sum(n, 0.0), sumSq(n, 0.0);
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
