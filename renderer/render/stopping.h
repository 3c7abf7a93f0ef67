// The rules that end a render, whichever comes first: the pass budget (spp), the time limit, the
// target error, cancellation. One unit, so that the CLI and the server's workers stop alike, and a
// merge of pass ranges rendered elsewhere (target_error_merge.h) stops at the same pass for a
// target error. (The time limit and the pass budget of ranges rendered apart belong to whoever
// hands out the ranges: a merge has no clock.)
#pragma once

#include <atomic>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/interrupt.h"
#include "film/film.h"
#include "render/settings.h"

namespace caustic {

/// Thrown when a render is cancelled before its first pass (while its session is built).
struct RenderCancelled : std::runtime_error {
    RenderCancelled() : std::runtime_error("cancelled") {}
};

/// Why a render stopped.
enum class StopReason { Spp, TimeLimit, TargetError, Cancelled };
std::string toString(StopReason r);

/// The fewest passes a render stops on its target error after. An error estimate needs
/// kMinPassesForError. A film that tracks the photon maps' bias (Film::tracksBias) needs
/// kMinPassesWithBias: over fewer passes the bias layer's mean is within its own noise, so its
/// estimate is clamped to 0 and the noise alone would stop the render. docs/study/trust.md measures
/// the estimate from 8 passes on.
constexpr int kMinPassesForError = 2;
constexpr int kMinPassesWithBias = 8;
int minPassesForTarget(const Film& film);

/// Whether a film of every pass from the first on has reached `targetError` (relative RMS, as
/// Film::relativeError; 0 for no target), with at least minPassesForTarget(film) passes.
bool reachedTargetError(const Film& film, double targetError);

/// How the time limit treats a render.
struct TimeLimitOptions {
    /// Seconds rendered by the earlier attempts of a resumed job: the limit counts them.
    double secondsBefore = 0;
    /// Whether a first pass still running at the limit is cut short too, so that the render ends
    /// with no pass (a service, whose jobs must end at their limit). Otherwise the first pass
    /// always finishes, so that a render has an image.
    bool strict = false;
};

class StopRules {
public:
    /// `cancel` (may be null) must outlive the rules.
    StopRules(const RenderSettings& settings, const std::atomic<bool>* cancel,
              TimeLimitOptions timeLimit = {});

    /// Starts the time limit's clock, rendering onto `film`: a pass still running at the limit is
    /// abandoned once the film holds one (or at once, with TimeLimitOptions::strict).
    void start(const Film& film);
    /// What passes poll: cancellation, and the time limit once a pass is done. Thread-safe.
    const Interrupt& interrupt() const { return interrupt_; }
    /// Why a pass cut short by interrupt() stopped.
    StopReason interruptReason() const {
        return interrupt_.cancelled() ? StopReason::Cancelled : StopReason::TimeLimit;
    }
    /// After a pass was added to `film`: why to stop now, if anything says so. The target error
    /// counts only on a film of every pass from the first (a pass range rendered apart from its
    /// predecessors cannot know it; a merge of ranges finds the stop, see target_error_merge.h).
    /// `passesLeft`: whether the budget has passes after this one.
    std::optional<StopReason> afterPass(const Film& film, bool passesLeft);
    /// Seconds since start(), with TimeLimitOptions::secondsBefore.
    double elapsed() const;

private:
    void armTimeLimit();

    double timeLimit_;
    double targetError_;
    TimeLimitOptions options_;
    Interrupt interrupt_;
    Interrupt::Clock::time_point start_;
};

}  // namespace caustic
