// The forecast of a render's end: the target error's pass from the fitted convergence rate, the
// pass budget, the time limit, whichever comes first.
#include "render/forecast.h"

#include <gtest/gtest.h>

#include <cmath>

namespace caustic {
namespace {

// A render whose error is c * passes^slope, one second a pass, after `passes` passes.
std::vector<ProgressPoint> history(int passes, double c, double slope) {
    std::vector<ProgressPoint> h;
    for (int n = 1; n <= passes; ++n)
        h.push_back({n, double(n), n >= 2 ? c * std::pow(double(n), slope) : std::nan("")});
    return h;
}

TEST(Forecast, TheTargetErrorsPassFromTheFittedRate) {
    // Monte Carlo: 0.1 / sqrt(n) reaches 1% at n = 100.
    std::optional<StopForecast> f = forecastStop(history(8, 0.1, -0.5), 1000, 0.01, 0);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->reason, StopReason::TargetError);
    EXPECT_NEAR(f->slope, -0.5, 1e-9);
    EXPECT_NEAR(f->totalPasses, 100, 1e-6);
    EXPECT_NEAR(f->secondsLeft, 92, 1e-6);
    // A slower rate (ppm's -1/3) needs far more passes: 0.1 n^(-1/3) = 0.01 at n = 1000.
    f = forecastStop(history(8, 0.1, -1.0 / 3), 100000, 0.01, 0);
    ASSERT_TRUE(f);
    EXPECT_NEAR(f->totalPasses, 1000, 1e-6);
}

TEST(Forecast, TheBudgetOrTheTimeLimitWhenTheyComeFirst) {
    // The target would take 100 passes; the budget has 50.
    std::optional<StopForecast> f = forecastStop(history(8, 0.1, -0.5), 50, 0.01, 0);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->reason, StopReason::Spp);
    EXPECT_NEAR(f->secondsLeft, 42, 1e-9);
    // A time limit of 20 s, 8 spent.
    f = forecastStop(history(8, 0.1, -0.5), 50, 0.01, 20);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->reason, StopReason::TimeLimit);
    EXPECT_NEAR(f->secondsLeft, 12, 1e-9);
    // No target: the budget at the pace so far.
    f = forecastStop(history(8, 0.1, -0.5), 50, 0, 0);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->reason, StopReason::Spp);
    EXPECT_NEAR(f->secondsLeft, 42, 1e-9);
}

TEST(Forecast, NoRateIsAssumedBeforeFourErrorsNorTrustedWhenFlat) {
    // Three passes: two errors, no fit; the budget.
    std::optional<StopForecast> f = forecastStop(history(3, 0.1, -0.5), 50, 0.01, 0);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->reason, StopReason::Spp);
    EXPECT_EQ(f->slope, 0);
    // An error that does not fall never reaches the target.
    f = forecastStop(history(16, 0.1, -0.01), 50, 0.01, 0);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->reason, StopReason::Spp);
    // Reached already: nothing left.
    f = forecastStop(history(16, 0.1, -0.5), 50, 0.05, 0);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->reason, StopReason::TargetError);
    EXPECT_EQ(f->secondsLeft, 0);
    EXPECT_FALSE(forecastStop({}, 50, 0.01, 0));
}

TEST(Forecast, ABiasedRenderStopsOnItsTargetNoEarlierThanItsFewestPasses) {
    // Reached at pass 4, but a film with the maps' bias stops on its target from pass 8 on: four
    // more seconds.
    std::optional<StopForecast> f = forecastStop(history(4, 0.01, -0.5), 50, 0.05, 0, 8);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->reason, StopReason::TargetError);
    EXPECT_EQ(f->totalPasses, 8);
    EXPECT_NEAR(f->secondsLeft, 4, 1e-9);
    // Predicted for pass 6 by the fitted rate (0.1 / sqrt(n) = 0.0408 at n = 6): pass 8 still.
    f = forecastStop(history(5, 0.1, -0.5), 50, 0.1 / std::sqrt(6.0), 0, 8);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->reason, StopReason::TargetError);
    EXPECT_NEAR(f->totalPasses, 8, 1e-9);
    // A budget of 6 passes ends it first.
    f = forecastStop(history(4, 0.01, -0.5), 6, 0.05, 0, 8);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->reason, StopReason::Spp);
    EXPECT_EQ(f->totalPasses, 6);
}

TEST(Forecast, APaceFromThisRunsPassesAlone) {
    // A render resumed at pass 10 after 100 s of an earlier attempt, now 2 s a pass.
    std::vector<ProgressPoint> h{{10, 100.0, 0.1 / std::sqrt(10.0)}};
    for (int n = 11; n <= 14; ++n)
        h.push_back({n, 100.0 + 2 * (n - 10), 0.1 / std::sqrt(double(n))});
    std::optional<StopForecast> f = forecastStop(h, 30, 0, 0);
    ASSERT_TRUE(f);
    EXPECT_NEAR(f->secondsLeft, 2 * 16, 1e-9);
}

}  // namespace
}  // namespace caustic
