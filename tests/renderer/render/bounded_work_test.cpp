// Loops whose length the settings control stop within moments of a cancel, mid-pass included. The
// trap (found by fuzzing): a point light inside a closed mirror sphere, max_depth 1e6. Perfect
// mirrors never end a path by Russian roulette, so every photon path and every camera path
// bounces a million times: a pass would take many minutes, the memory check's pilot tracing too.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

#include "accel/accelerator.h"
#include "integrators/integrator.h"
#include "photons/photon_tracer.h"
#include "render/integrator_factory.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using Clock = std::chrono::steady_clock;
using testing::sceneFromJson;
using testing::settingsFrom;

nlohmann::json mirrorTrap() {
    return nlohmann::json::parse(R"({
      "camera": {"position": [0, 0, 0], "look_at": [0, 0, 1], "fov": 60, "width": 32,
                 "height": 32},
      "materials": {"mirror": {"type": "mirror", "reflectance": [1, 1, 1]}},
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "flip_normals": true,
                  "material": "mirror"}],
      "lights": [{"type": "point", "position": [0, 0.5, 0], "intensity": [1, 1, 1]}]
    })");
}

RenderSettings trapSettings(const std::string& integrator) {
    return settingsFrom({{"integrator", integrator}, {"max_depth", 1000000}, {"threads", 2}});
}

// Seconds from setting `cancel` (after `delay`) until `work` returns.
template <typename Work>
double secondsToStop(std::atomic<bool>& cancel, Work work, std::chrono::milliseconds delay) {
    auto done = std::async(std::launch::async, work);
    EXPECT_EQ(done.wait_for(delay), std::future_status::timeout) << "finished before the cancel";
    auto t0 = Clock::now();
    cancel = true;
    EXPECT_EQ(done.wait_for(std::chrono::seconds(5)), std::future_status::ready);
    done.get();
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Renders, cancels after `delay`, and expects the render to end as cancelled within two seconds
// (well under a second in a release build; the sanitizer build and a loaded machine are slower).
void expectCancelledSoon(const Scene& scene, const RenderSettings& settings,
                         std::chrono::milliseconds delay) {
    std::atomic<bool> cancel{false};
    StopReason reason = StopReason::Spp;
    double seconds = secondsToStop(
        cancel,
        [&] {
            RenderCallbacks callbacks;
            callbacks.cancel = &cancel;
            try {
                reason = render(scene, settings, callbacks).stats.stopReason;
            } catch (const RenderCancelled&) {
                reason = StopReason::Cancelled;  // while the session was built (the pilot)
            }
        },
        delay);
    EXPECT_EQ(reason, StopReason::Cancelled);
    EXPECT_LT(seconds, 2.0);
}

class BoundedWork : public ::testing::TestWithParam<std::string> {};

TEST_P(BoundedWork, ACancelStopsARenderOfEndlessPathsWithinASecond) {
    auto scene = sceneFromJson(mirrorTrap());
    expectCancelledSoon(*scene, trapSettings(GetParam()), std::chrono::milliseconds(500));
}

INSTANTIATE_TEST_SUITE_P(Integrators, BoundedWork,
                         ::testing::Values("path", "whitted", "photon", "ppm"),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

TEST(BoundedWork, ACancelStopsAPassOfAMillionSamplesPerPixel) {
    // Ray casting ends every path at once; the work is in the pixel samples' loop.
    auto scene = sceneFromJson(testing::exampleScene("cornell-spheres", 64, 64));
    nlohmann::json s = {{"integrator", "raycast"}, {"spp", 1000000}, {"threads", 2}};
    s["spp_per_pass"] = 1000000;
    expectCancelledSoon(*scene, settingsFrom(s), std::chrono::milliseconds(500));
}

TEST(BoundedWork, AStrictTimeLimitCutsTheFirstPassAndThePilot) {
    // What the service asks: a job's time limit holds for its first pass and its memory check.
    auto scene = sceneFromJson(mirrorTrap());
    for (const char* integrator : {"path", "photon"}) {
        nlohmann::json s = {{"integrator", integrator},
                            {"max_depth", 1000000},
                            {"time_limit", 1.0},
                            {"threads", 2}};
        RenderCallbacks callbacks;
        callbacks.timeLimit = {.secondsBefore = 0.5, .strict = true};
        auto t0 = Clock::now();
        StopReason reason = StopReason::Spp;
        int passes = -1;
        try {
            RenderResult r = render(*scene, settingsFrom(s), callbacks);
            reason = r.stats.stopReason;
            passes = r.film->passes();
        } catch (const RenderCancelled&) {
            reason = StopReason::TimeLimit;  // in the pilot, before any pass
            passes = 0;
        }
        double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        EXPECT_EQ(reason, StopReason::TimeLimit) << integrator;
        EXPECT_EQ(passes, 0) << integrator;
        // The half second of an earlier attempt counts against the limit.
        EXPECT_LT(seconds, 2.0) << integrator;
        EXPECT_GT(seconds, 0.4) << integrator;
    }
}

TEST(BoundedWork, PhotonTracingStopsMidPass) {
    auto scene = sceneFromJson(mirrorTrap());
    auto accel = createAccelerator("embree", scene->geometry);
    std::atomic<bool> cancel{false};
    Interrupt interrupt(&cancel);
    PhotonTracingOptions options;
    options.photons = 100000;
    options.maxDepth = 1000000;
    options.interrupt = &interrupt;
    PhotonTracing traced;
    double seconds = secondsToStop(
        cancel, [&] { traced = tracePhotons(*scene, *accel, options); },
        std::chrono::milliseconds(300));
    EXPECT_TRUE(traced.interrupted);
    EXPECT_LT(seconds, 2.0);
}

TEST(BoundedWork, APhotonPassStopsWhenItsIntegratorIsInterrupted) {
    auto scene = sceneFromJson(mirrorTrap());
    auto accel = createAccelerator("embree", scene->geometry);
    std::unique_ptr<Integrator> integrator = createIntegrator(*scene, *accel, trapSettings("ppm"));
    std::atomic<bool> cancel{false};
    Interrupt interrupt(&cancel);
    integrator->setInterrupt(&interrupt);
    double seconds = secondsToStop(
        cancel, [&] { integrator->beginPass(3); }, std::chrono::milliseconds(300));
    EXPECT_LT(seconds, 2.0);
}

TEST(BoundedWork, ATimeLimitCutsShortAPassAfterTheFirst) {
    // The first pass is quick (max_depth 1), so the time limit's clock can be armed; the
    // session's later passes would take minutes and must stop at the limit.
    auto scene = sceneFromJson(mirrorTrap());
    nlohmann::json s = {{"integrator", "path"}, {"max_depth", 1000000}, {"spp", 4},
                        {"spp_per_pass", 1},    {"time_limit", 0.5},    {"threads", 2}};
    RenderSession session(*scene, settingsFrom(s));
    std::unique_ptr<Film> film = session.makeFilm();
    // Pass 0 rendered by a session whose paths end at once stands for a quick first pass.
    nlohmann::json quick = s;
    quick["max_depth"] = 1;
    RenderSession(*scene, settingsFrom(quick)).renderRange(0, 1, *film, {});
    auto t0 = Clock::now();
    RangeResult r = session.renderRange(1, 4, *film, {});
    double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    EXPECT_EQ(r.stopReason, StopReason::TimeLimit);
    EXPECT_EQ(film->passes(), 1);
    EXPECT_LT(seconds, 2.5);
}

}  // namespace
}  // namespace caustic
