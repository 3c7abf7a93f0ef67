// The render loop shared by every integrator: the stopping rules (spp, time limit, target error,
// cancellation; whichever comes first), the stats every render reports, and its callbacks.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>

#include "core/error.h"
#include "integrators/integrator.h"
#include "render/integrator_factory.h"
#include "render/stopping.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using nlohmann::json;
using testing::exampleScene;
using testing::sceneFromJson;
using testing::settingsFrom;

constexpr int kWidth = 32, kHeight = 24;

std::unique_ptr<Scene> cornell() {
    return sceneFromJson(exampleScene("cornell-spheres", kWidth, kHeight));
}

class RenderLoop : public ::testing::TestWithParam<std::string> {};

TEST_P(RenderLoop, StopsBySppWithConsistentStats) {
    auto scene = cornell();
    RenderResult r =
        render(*scene,
               settingsFrom(
                   {{"integrator", GetParam()}, {"spp", 12}, {"spp_per_pass", 3}, {"threads", 2}}));
    const RenderStats& s = r.stats;
    EXPECT_EQ(s.stopReason, StopReason::Spp);
    EXPECT_EQ(s.passes, 4);
    EXPECT_EQ(s.sppReached, 12);
    EXPECT_EQ(r.film->passes(), 4);
    EXPECT_EQ(s.samples, uint64_t(kWidth) * kHeight * 12);
    EXPECT_EQ(s.threads, 2);
    // Every camera sample traces at least its camera ray.
    EXPECT_GE(s.rays, s.samples);
    EXPECT_DOUBLE_EQ(s.raysPerSecond, double(s.rays) / s.renderSeconds);
    EXPECT_NEAR(s.setupSeconds, s.acceleratorSeconds + s.integratorSeconds, 1e-3);
    EXPECT_GE(s.totalSeconds, s.setupSeconds + s.renderSeconds);
    EXPECT_DOUBLE_EQ(s.relativeError, r.film->relativeError());
    EXPECT_GT(s.relativeError, 0.0);
    EXPECT_EQ(s.droppedSamples, 0u);

    json j = s.toJson();
    for (const char* key :
         {"setup_seconds", "accelerator_seconds", "integrator_seconds", "render_seconds",
          "pass_setup_seconds", "total_seconds", "rays", "samples", "rays_per_second", "passes",
          "spp", "relative_error", "dropped_samples", "threads", "stop_reason", "memory"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j["stop_reason"], "spp");
}

TEST_P(RenderLoop, StopsAtTargetErrorBeforeSpp) {
    auto scene = cornell();
    // 20% relative error is reached within a few passes by every integrator at this size; the
    // 4096 spp budget would take hundreds of passes.
    std::vector<double> errors;
    RenderCallbacks callbacks;
    callbacks.onPass = [&](const Film& film) { errors.push_back(film.relativeError()); };
    RenderResult r = render(*scene,
                            settingsFrom({{"integrator", GetParam()},
                                          {"spp", 4096},
                                          {"spp_per_pass", 2},
                                          {"target_error", 0.2}}),
                            callbacks);
    EXPECT_EQ(r.stats.stopReason, StopReason::TargetError);
    // An error estimate needs two passes; one with the photon maps' bias, eight.
    const int fewest = minPassesForTarget(*r.film);
    EXPECT_EQ(fewest, r.film->tracksBias() ? kMinPassesWithBias : kMinPassesForError);
    EXPECT_GE(r.stats.passes, fewest);
    EXPECT_LT(r.stats.passes, 2048);
    EXPECT_LE(r.stats.relativeError, 0.2);
    EXPECT_EQ(r.stats.sppReached, 2 * r.stats.passes);
    // It stopped at the first pass from its fewest on that reached the target.
    ASSERT_EQ(errors.size(), size_t(r.stats.passes));
    for (size_t i = size_t(fewest) - 1; i + 1 < errors.size(); ++i)
        EXPECT_GT(errors[i], 0.2) << "pass " << i + 1;
}

TEST_P(RenderLoop, StopsAtTimeLimitAfterWholePasses) {
    auto scene = cornell();
    RenderResult r = render(*scene, settingsFrom({{"integrator", GetParam()},
                                                  {"spp", 100000},
                                                  {"spp_per_pass", 1},
                                                  {"time_limit", 0.05}}));
    EXPECT_EQ(r.stats.stopReason, StopReason::TimeLimit);
    EXPECT_GE(r.stats.passes, 1);  // the first pass always completes
    EXPECT_LT(r.stats.passes, 100000);
    EXPECT_EQ(r.film->passes(), r.stats.passes);
    EXPECT_EQ(r.stats.sppReached, r.stats.passes);
}

TEST_P(RenderLoop, CancellationStopsAndKeepsOnlyWholePasses) {
    auto scene = cornell();
    std::atomic<bool> cancel{false};
    int passesSeen = 0;
    RenderCallbacks callbacks;
    callbacks.cancel = &cancel;
    callbacks.onPass = [&](const Film& film) {
        passesSeen = film.passes();
        if (film.passes() == 3) cancel = true;
    };
    RenderResult r =
        render(*scene, settingsFrom({{"integrator", GetParam()}, {"spp", 64}, {"spp_per_pass", 1}}),
               callbacks);
    EXPECT_EQ(r.stats.stopReason, StopReason::Cancelled);
    EXPECT_EQ(r.stats.passes, 3);
    EXPECT_EQ(passesSeen, 3);
}

TEST_P(RenderLoop, ProgressIsMonotonicAndEndsComplete) {
    auto scene = cornell();
    std::vector<RenderProgress> seen;
    RenderCallbacks callbacks;
    callbacks.onProgress = [&](const RenderProgress& p) { seen.push_back(p); };
    render(*scene, settingsFrom({{"integrator", GetParam()}, {"spp", 8}, {"spp_per_pass", 1}}),
           callbacks);
    ASSERT_FALSE(seen.empty());
    for (size_t i = 1; i < seen.size(); ++i) {
        EXPECT_GE(seen[i].fraction, seen[i - 1].fraction);
        EXPECT_GE(seen[i].passesDone, seen[i - 1].passesDone);
    }
    EXPECT_EQ(seen.back().fraction, 1.0);
    EXPECT_EQ(seen.back().passesDone, 8);
    EXPECT_EQ(seen.back().passesTotal, 8);
    EXPECT_TRUE(std::isfinite(seen.back().relativeError));
}

TEST_P(RenderLoop, ResumesFromACheckpointToTheSameImage) {
    // What a restarted server does: keep the film after some pass, render again from it.
    auto scene = cornell();
    RenderSettings settings = settingsFrom(
        {{"integrator", GetParam()}, {"spp", 10}, {"spp_per_pass", 2}, {"photons", 5000}});
    std::unique_ptr<Film> checkpoint;
    RenderCallbacks keep;
    keep.onPass = [&](const Film& film) {
        if (film.passes() == 2) checkpoint = std::make_unique<Film>(film);
    };
    RenderResult whole = render(*scene, settings, keep);
    ASSERT_TRUE(checkpoint);
    RenderSession session(*scene, settings);
    int firstPassSeen = 0;
    RenderCallbacks resume;
    resume.onPass = [&](const Film& film) {
        if (firstPassSeen == 0) firstPassSeen = film.passes();
    };
    Film resumed = *checkpoint;
    RenderStats stats = renderPasses(session, resumed, resume);
    EXPECT_EQ(firstPassSeen, 3);
    EXPECT_EQ(stats.passes, 5);
    EXPECT_TRUE(resumed == *whole.film);

    // A finished checkpoint renders nothing more.
    Film again = *whole.film;
    EXPECT_EQ(renderPasses(session, again).passes, 5);
    EXPECT_TRUE(again == *whole.film);

    // A checkpoint of another size is refused.
    Film other(kWidth + 1, kHeight);
    EXPECT_THROW(renderPasses(session, other), InputError);
}

INSTANTIATE_TEST_SUITE_P(Integrators, RenderLoop, ::testing::ValuesIn(integratorNames()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

}  // namespace
}  // namespace caustic
