// The rules that end a render, whichever comes first: the pass budget (spp), the time limit, the
// target error, cancellation. One unit, so that the CLI, the server's workers and a merge of pass
// ranges rendered elsewhere stop at the same pass.
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

/// Whether a film of every pass from the first on has reached `targetError` (relative RMS, as
/// Film::relativeError; 0 for no target). Needs two passes.
bool reachedTargetError(const Film& film, double targetError);

class StopRules {
public:
    /// `cancel` (may be null) must outlive the rules.
    StopRules(const RenderSettings& settings, const std::atomic<bool>* cancel);

    /// Starts the time limit's clock. Rendering onto `film`: once it holds a pass, a pass still
    /// running at the time limit is abandoned; the first is always finished, so that a render has
    /// an image (the caller may cancel it).
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
    /// Seconds since start().
    double elapsed() const;

private:
    void armTimeLimit();

    double timeLimit_;
    double targetError_;
    Interrupt interrupt_;
    Interrupt::Clock::time_point start_;
};

}  // namespace caustic
