// When will a render stop? After each pass, the seconds left until whichever rule ends it first:
// the pass budget (spp), the time limit, or the target error. The target error's pass is predicted
// from the measured convergence rate: the slope of log(relative error) against log(passes), fitted
// by least squares over the passes so far (Monte Carlo's is -1/2; photon mapping's reported error,
// its pass variance, falls alike). Nothing is assumed of the rate until four passes have an error.
#pragma once

#include <optional>
#include <vector>

#include "render/stopping.h"

namespace caustic {

/// The render after a pass: its passes (from the first), the seconds spent on them, its error.
struct ProgressPoint {
    int passes = 0;
    double seconds = 0;
    double relativeError = 0;  ///< NaN before two passes.
};

struct StopForecast {
    double secondsLeft = 0;
    StopReason reason = StopReason::Spp;
    double totalPasses = 0;  ///< The pass it stops after, predicted (fractional for the target).
    double slope = 0;        ///< The fitted log-log rate (0 when not fitted).
};

/// The forecast after the last point of `history` (points in pass order); nothing before the first
/// pass. `targetError` and `timeLimit` are 0 when not set; the target stops no earlier than
/// `minTargetPasses` (minPassesForTarget, render/stopping.h).
std::optional<StopForecast> forecastStop(const std::vector<ProgressPoint>& history, int passesTotal,
                                         double targetError, double timeLimit,
                                         int minTargetPasses = kMinPassesForError);

}  // namespace caustic
