// A job rendered as pass ranges anywhere, merged in any order, is the job rendered whole: the same
// sums, sums of squares, pass set, stop pass and EXR bytes, for every integrator, with and without
// a target error. And a pass is never counted twice.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numeric>
#include <random>

#include "film/image_io.h"
#include "integrators/integrator.h"
#include "render/target_error_merge.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using testing::exampleScene;
using testing::sceneFromJson;
using testing::settingsFrom;

constexpr int kPasses = 16;
// Random partitions tried per integrator, with and without a target error.
constexpr int kPartitions = 12;

// Cut points splitting [0, kPasses) into 2 to 7 ranges.
std::vector<int> randomCuts(std::mt19937& rng) {
    int ranges = std::uniform_int_distribution<int>(2, 7)(rng);
    std::vector<int> inner(kPasses - 1);
    std::iota(inner.begin(), inner.end(), 1);
    std::shuffle(inner.begin(), inner.end(), rng);
    std::vector<int> cuts(inner.begin(), inner.begin() + (ranges - 1));
    cuts.push_back(0);
    cuts.push_back(kPasses);
    std::sort(cuts.begin(), cuts.end());
    return cuts;
}

std::string exrBytes(const Film& film, const std::string& name) {
    auto file = std::filesystem::temp_directory_path() /
                ("caustic-range-" + std::to_string(getpid()) + "-" + name + ".exr");
    writeImage(file, RgbImage{film.width(), film.height(), film.meanRgb()});
    std::ifstream in(file, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::filesystem::remove(file);
    return bytes;
}

// An integrator and a sampler.
class PassRanges : public ::testing::TestWithParam<std::tuple<std::string, std::string>> {
protected:
    void SetUp() override {
        scene_ = sceneFromJson(exampleScene("cornell-spheres", 24, 16));
        const auto& [integrator, sampler] = GetParam();
        // Four samples per pass, so that the sobol sampler's points within a pass are a set, and
        // adaptive sampling (sobol, samples by the pilot's 8 passes: a range after them renders
        // the pilot again) has samples to move.
        json_ = testing::integratorVariant(integrator);
        json_.merge_patch({{"spp", 4 * kPasses},
                           {"spp_per_pass", 4},
                           {"photons", 3000},
                           {"seed", 7},
                           {"threads", 2},
                           {"sampler", sampler == "adaptive"            ? "sobol"
                                       : sampler == "adaptive_sequence" ? "sobol_sequence"
                                                                        : sampler},
                           {"adaptive", sampler.starts_with("adaptive")}});
    }
    RenderSettings settings(double targetError) const {
        nlohmann::json j = json_;
        j["target_error"] = targetError;
        return settingsFrom(j);
    }

    std::unique_ptr<Scene> scene_;
    nlohmann::json json_;
};

TEST_P(PassRanges, AnyPartitionMergedInAnyOrderIsTheWholeRender) {
    RenderResult whole = render(*scene_, settings(0));
    ASSERT_EQ(whole.film->passes(), kPasses);
    const std::string wholeExr = exrBytes(*whole.film, "whole");
    std::mt19937 rng(1234);
    for (int trial = 0; trial < kPartitions; ++trial) {
        std::vector<int> cuts = randomCuts(rng);
        std::vector<Film> parts;
        for (size_t r = 0; r + 1 < cuts.size(); ++r) {
            RenderSession session(*scene_, settings(0));  // as if on another worker
            parts.push_back(*session.makeFilm());
            session.renderRange(cuts[r], cuts[r + 1], parts.back(), {});
        }
        std::shuffle(parts.begin(), parts.end(), rng);
        Film merged = parts[0];
        for (size_t i = 1; i < parts.size(); ++i) merged.merge(parts[i]);
        SCOPED_TRACE("partition " + std::to_string(trial) + " into " +
                     std::to_string(parts.size()) + " ranges");
        EXPECT_TRUE(merged == *whole.film);
        EXPECT_EQ(merged.sums(), whole.film->sums());
        EXPECT_EQ(merged.sumsOfSquares(), whole.film->sumsOfSquares());
        EXPECT_EQ(merged.passSet(), whole.film->passSet());
        EXPECT_EQ(exrBytes(merged, "merged"), wholeExr);
        // Merging a range again, or one overlapping it, is refused and changes nothing.
        EXPECT_THROW(merged.merge(parts[0]), std::invalid_argument);
        EXPECT_TRUE(merged == *whole.film);
    }
}

TEST_P(PassRanges, TargetErrorStopsAtTheSamePassWhateverTheSplit) {
    // A target the whole render reaches about half way.
    std::vector<double> errors;
    RenderCallbacks record;
    record.onPass = [&](const Film& film) { errors.push_back(film.relativeError()); };
    render(*scene_, settings(0), record);
    const double target = errors[kPasses / 2];
    RenderResult whole = render(*scene_, settings(target));
    ASSERT_EQ(whole.stats.stopReason, StopReason::TargetError);
    ASSERT_LT(whole.film->passes(), kPasses);
    const int stopPass = whole.film->passes() - 1;
    const std::string wholeExr = exrBytes(*whole.film, "whole-target");

    std::mt19937 rng(99);
    for (int trial = 0; trial < kPartitions; ++trial) {
        std::vector<int> cuts = randomCuts(rng);
        // Each range on its own session, its passes kept for the ordered merge.
        struct Pass {
            int index;
            std::vector<Color> image;
            uint64_t dropped;
        };
        std::vector<std::vector<Pass>> ranges(cuts.size() - 1);
        for (size_t r = 0; r + 1 < cuts.size(); ++r) {
            RenderSession session(*scene_, settings(target));
            RenderCallbacks keep;
            keep.onPassImage = [&](int p, const std::vector<Color>& image, uint64_t dropped) {
                ranges[r].push_back({p, image, dropped});
            };
            std::unique_ptr<Film> film = session.makeFilm();
            session.renderRange(cuts[r], cuts[r + 1], *film, keep);
        }
        std::shuffle(ranges.begin(), ranges.end(), rng);
        TargetErrorMerge merge(whole.film->width(), whole.film->height(), target,
                               whole.film->tracksBias());
        for (std::vector<Pass>& range : ranges)
            for (Pass& p : range) merge.addPass(p.index, std::move(p.image), p.dropped);
        SCOPED_TRACE("partition " + std::to_string(trial) + " into " +
                     std::to_string(cuts.size() - 1) + " ranges");
        ASSERT_TRUE(merge.stopPass());
        EXPECT_EQ(*merge.stopPass(), stopPass);
        EXPECT_EQ(merge.pending(), 0u);
        EXPECT_TRUE(merge.film() == *whole.film);
        EXPECT_EQ(merge.film().sums(), whole.film->sums());
        EXPECT_EQ(merge.film().sumsOfSquares(), whole.film->sumsOfSquares());
        EXPECT_EQ(exrBytes(merge.film(), "merged-target"), wholeExr);
        EXPECT_THROW(merge.addPass(0, {}, 0), std::invalid_argument);
    }
}

INSTANTIATE_TEST_SUITE_P(
    IntegratorsAndSamplers, PassRanges,
    ::testing::Combine(::testing::ValuesIn(testing::integratorVariants()),
                       ::testing::Values("independent", "sobol", "sobol_sequence", "adaptive",
                                         "adaptive_sequence")),
    [](const ::testing::TestParamInfo<std::tuple<std::string, std::string>>& p) {
        return std::get<0>(p.param) + "_" + std::get<1>(p.param);
    });

}  // namespace
}  // namespace caustic
