// Can users trust the error a render reports? For the path tracer on every example scene, at a
// reduced size (docs/study/README.md has the full-size figures): the relative error estimated from
// the pass variance against the true relative error (against a long reference, less the
// reference's own noise), at several pass counts, within 0.8 to 1.25; and the share of pixel
// values whose 95% Student-t interval from the passes holds the reference. With sobol_sequence,
// whose passes are not independent, the reported error must not be below the true one.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "core/student_t.h"
#include "render/renderer.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using nlohmann::json;
using testing::exampleScene;
using testing::sceneFromJson;
using testing::settingsFrom;

constexpr int kSize = 24;

struct Trust {
    double reported = 0;  ///< The relative error the film reports.
    double truth = 0;     ///< Its relative error against the reference, less the reference's noise.
    double coverage = 0;  ///< Share of pixel values inside their 95% interval.
};

Trust trustOf(const Film& film, const std::vector<float>& ref, const std::vector<float>& refSe) {
    const std::vector<float> mean = film.meanRgb(), se = film.standardErrorRgb();
    const double t = studentThreshold(0.05, film.passes() - 1);
    double sqErr = 0, refVar = 0, refSq = 0;
    size_t covered = 0;
    for (size_t i = 0; i < mean.size(); ++i) {
        const double d = double(mean[i]) - ref[i];
        sqErr += d * d;
        refVar += double(refSe[i]) * refSe[i];
        refSq += double(ref[i]) * ref[i];
        covered += std::abs(d) <= t * std::hypot(double(se[i]), double(refSe[i]));
    }
    return {film.relativeError(), std::sqrt(std::max(0.0, sqErr - refVar) / refSq),
            double(covered) / double(mean.size())};
}

class ErrorTrust : public ::testing::TestWithParam<std::string> {};

// The per-pixel intervals are t intervals: right when a pixel's pass estimates are near normal.
// Where rare paths carry much of a pixel's light they are not: most passes miss those paths, the
// spread of the passes misses them too, and the interval misses the reference. That is the case
// of every pixel lit through glass (cornell-spheres' and caustic-glass' caustics, which path
// tracing finds only by chance: measured 73% and 80% at 32 passes, and 62% to 87% at 96 x 96 in
// docs/study/README.md), and a little of every pixel straddling the lamp's edge (measured 91% to
// 93% on the other scenes). The bounds hold what was measured, less a margin; the study reports
// the full-size figures.
bool rarePathsCarryTheError(const std::string& scene) {
    return scene == "cornell-spheres" || scene == "caustic-glass";
}
double leastCoverage(const std::string& scene) {
    return rarePathsCarryTheError(scene) ? 0.70 : 0.88;
}

// The same holds for the image's reported error: on caustic-glass, whose error is mostly its
// caustic once the lamp's edges are resolved by emission_samples (render/seen_emission.h), the
// reported error is below the true one at few passes (measured over 8 seeds: 0.74, 0.83 and 0.97
// of it at 8, 16 and 32 passes; with the lamp's edges from the samples' own rays, whose noise the
// passes' spread does see, 1.14, 1.03 and 0.82 over 4 seeds). The bound holds what was measured,
// less a margin, over twice the seeds for these scenes (one render's true error there scattered
// from 0.07 to 0.18 between seeds).
double leastRatio(const std::string& scene) {
    return rarePathsCarryTheError(scene) ? 0.65 : 0.8;
}
constexpr int kSeeds = 4;
int seeds(const std::string& scene) {
    return rarePathsCarryTheError(scene) ? 2 * kSeeds : kSeeds;
}

constexpr int kRungs[] = {8, 16, 32};  // passes of 4 samples

// One render's error is dominated by its few noisiest pixels, so both the reported and the true
// error of one render scatter by tens of percent from seed to seed (measured: 0.64 to 1.71 for the
// cornell box with emission_samples 0, whose noisiest pixels are then the lamp's edges). The check
// is on their expectation: the ratio of their RMS over 4 seeds (8 where rare paths carry the
// error). The reference has 64 times the samples of the checked renders at their end, so its noise
// is a small correction.
TEST_P(ErrorTrust, ReportedErrorTracksTheTrueErrorAndIntervalsCoverTheReference) {
    auto scene = sceneFromJson(exampleScene(GetParam(), kSize, kSize));
    RenderResult ref =
        render(*scene, settingsFrom({{"spp", 8192}, {"spp_per_pass", 128}, {"seed", 1000003}}));
    const std::vector<float> refMean = ref.film->meanRgb(), refSe = ref.film->standardErrorRgb();

    std::map<int, std::vector<Trust>> rungs;
    const int seedCount = seeds(GetParam());
    for (int seed = 1; seed <= seedCount; ++seed) {
        RenderCallbacks callbacks;
        callbacks.onPass = [&](const Film& film) {
            for (int passes : kRungs)
                if (film.passes() == passes) rungs[passes].push_back(trustOf(film, refMean, refSe));
        };
        render(*scene, settingsFrom({{"spp", 128}, {"spp_per_pass", 4}, {"seed", seed}}),
               callbacks);
    }
    for (int passes : kRungs) {
        const std::vector<Trust>& t = rungs[passes];
        ASSERT_EQ(t.size(), size_t(seedCount));
        double reported = 0, truth = 0, coverage = 0;
        for (const Trust& r : t) {
            reported += r.reported * r.reported;
            truth += r.truth * r.truth;
            coverage += r.coverage / seedCount;
        }
        const double ratio = std::sqrt(reported / truth);
        std::printf("  %s, %d passes: reported / true error %.3f, 95%% coverage %.1f%%\n",
                    GetParam().c_str(), passes, ratio, 100 * coverage);
        EXPECT_GE(ratio, leastRatio(GetParam())) << passes << " passes";
        EXPECT_LE(ratio, 1.25) << passes << " passes";
        EXPECT_LE(coverage, 0.99) << passes << " passes";
        if (passes == 32) {
            EXPECT_GE(coverage, leastCoverage(GetParam()));
        }
    }
}

// sobol_sequence runs one Sobol' sequence through a pixel's passes: they fill each other's gaps,
// so their mean is more accurate than their spread says, and the reported error is an
// overestimate (the setting's documentation says so). Checked: not an underestimate, at 8, 16 and
// 32 passes of 4 samples, on scenes without caustics (those with them are at the Monte Carlo rate
// either way: their error is the few paths that find the lamp through glass). Measured 1.98 to
// 3.10 on cornell-box and bunny, 1.10 to 1.14 on indirect; the bound, 0.9, is the trust test's
// lower one with half its margin.
TEST(ErrorTrustOfSobolSequence, ReportedErrorIsNotBelowTheTrueError) {
    for (const std::string name : {"cornell-box", "bunny", "indirect"}) {
        auto scene = sceneFromJson(exampleScene(name, kSize, kSize));
        RenderResult ref =
            render(*scene, settingsFrom({{"spp", 8192}, {"spp_per_pass", 128}, {"seed", 1000003}}));
        const std::vector<float> refMean = ref.film->meanRgb(),
                                 refSe = ref.film->standardErrorRgb();
        std::map<int, double> reported, truth;
        for (int seed = 1; seed <= kSeeds; ++seed) {
            RenderCallbacks callbacks;
            callbacks.onPass = [&](const Film& film) {
                for (int passes : kRungs) {
                    if (film.passes() != passes) continue;
                    const Trust t = trustOf(film, refMean, refSe);
                    reported[passes] += t.reported * t.reported;
                    truth[passes] += t.truth * t.truth;
                }
            };
            render(*scene,
                   settingsFrom({{"spp", 128},
                                 {"spp_per_pass", 4},
                                 {"sampler", "sobol_sequence"},
                                 {"seed", seed}}),
                   callbacks);
        }
        for (int passes : kRungs) {
            const double ratio = std::sqrt(reported[passes] / truth[passes]);
            std::printf("  %s, sobol_sequence, %d passes: reported / true error %.3f\n",
                        name.c_str(), passes, ratio);
            EXPECT_GE(ratio, 0.9) << name << ", " << passes << " passes";
        }
    }
}

// The photon maps' bias is in their error estimate (film/film.h, the bias layer): the reported
// error, noise plus bias, against the true error, for photon-mapped configurations at 8, 16 and 32
// passes of 4 samples over kSeeds seeds (the reference is the path tracer's). On scenes where the
// error is not the lamp's edges or rare paths through glass (cornell-box and caustic-glass: their
// ratio is the path tracer's own, above), so that the maps' part of the error shows. Measured
// (24^2): 0.80 to 1.05 at the default radii; with a radius far past the default (ppm_blurred, 0.4
// with 50,000 photons a pass) 0.74 to 0.95, where the noise alone would give 0.58 to 0.89: a bias
// that saturates at large radii grows slower than r^2, and the two-radius estimate
// (photons/photon_map.h) then reads it short. The bound below holds what was measured less a
// margin; the study's trust table (docs/study/README.md) is where the 0.8 to 1.25 goal is judged.
struct MappedConfig {
    const char* name;
    json settings;
};

class ErrorTrustOfPhotonMaps
    : public ::testing::TestWithParam<std::tuple<std::string, MappedConfig>> {};

TEST_P(ErrorTrustOfPhotonMaps, ReportedErrorWithBiasTracksTheTrueError) {
    const auto& [sceneName, config] = GetParam();
    auto scene = sceneFromJson(exampleScene(sceneName, kSize, kSize));
    RenderResult ref =
        render(*scene, settingsFrom({{"spp", 8192}, {"spp_per_pass", 128}, {"seed", 1000003}}));
    const std::vector<float> refMean = ref.film->meanRgb(), refSe = ref.film->standardErrorRgb();
    std::map<int, double> reported, noise, truth;
    for (int seed = 1; seed <= kSeeds; ++seed) {
        RenderCallbacks callbacks;
        callbacks.onPass = [&](const Film& film) {
            for (int passes : kRungs)
                if (film.passes() == passes) {
                    ASSERT_TRUE(film.tracksBias());
                    const Trust t = trustOf(film, refMean, refSe);
                    reported[passes] += t.reported * t.reported;
                    noise[passes] += film.relativeNoise() * film.relativeNoise();
                    truth[passes] += t.truth * t.truth;
                }
        };
        json settings = config.settings;
        settings.update({{"spp", 128}, {"spp_per_pass", 4}, {"seed", seed}});
        render(*scene, settingsFrom(settings), callbacks);
    }
    for (int passes : kRungs) {
        const double ratio = std::sqrt(reported[passes] / truth[passes]);
        const double noiseRatio = std::sqrt(noise[passes] / truth[passes]);
        std::printf("  %s, %s, %d passes: reported / true error %.3f (noise alone %.3f)\n",
                    sceneName.c_str(), config.name, passes, ratio, noiseRatio);
        EXPECT_GE(ratio, 0.7) << passes << " passes";
        EXPECT_LE(ratio, 1.25) << passes << " passes";
    }
}

INSTANTIATE_TEST_SUITE_P(
    ExampleScenes, ErrorTrustOfPhotonMaps,
    ::testing::Combine(
        ::testing::Values("cornell-spheres", "indirect"),
        ::testing::Values(
            MappedConfig{"ppm", {{"integrator", "ppm"}, {"photons", 20000}}},
            MappedConfig{
                "path_both",
                {{"integrator", "path"}, {"caustics", "photon_map"}, {"indirect", "photon_map"}}},
            MappedConfig{"photon_k50", {{"integrator", "photon"}, {"photons", 20000}}},
            MappedConfig{"ppm_blurred",
                         {{"integrator", "ppm"}, {"photons", 50000}, {"radius", 0.4}}})),
    [](const auto& p) {
        std::string name = std::get<0>(p.param) + "_" + std::get<1>(p.param).name;
        std::erase(name, '-');
        return name;
    });

INSTANTIATE_TEST_SUITE_P(ExampleScenes, ErrorTrust,
                         ::testing::Values("cornell-box", "cornell-spheres", "bunny",
                                           "caustic-glass", "meshes", "indirect"),
                         [](const ::testing::TestParamInfo<std::string>& p) {
                             std::string name = p.param;
                             std::erase(name, '-');
                             return name;
                         });

}  // namespace
}  // namespace caustic
