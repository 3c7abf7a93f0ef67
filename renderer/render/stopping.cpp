#include "render/stopping.h"

#include <chrono>

namespace caustic {

std::string toString(StopReason r) {
    switch (r) {
        case StopReason::Spp:
            return "spp";
        case StopReason::TimeLimit:
            return "time_limit";
        case StopReason::TargetError:
            return "target_error";
        case StopReason::Cancelled:
            return "cancelled";
    }
    return "unknown";
}

int minPassesForTarget(const Film& film) {
    return film.tracksBias() ? kMinPassesWithBias : kMinPassesForError;
}

bool reachedTargetError(const Film& film, double targetError) {
    return targetError > 0 && film.passes() >= minPassesForTarget(film) &&
           film.passSet().isPrefix() && film.relativeError() <= targetError;
}

StopRules::StopRules(const RenderSettings& settings, const std::atomic<bool>* cancel,
                     TimeLimitOptions timeLimit)
    : timeLimit_(settings.timeLimit),
      targetError_(settings.targetError),
      options_(timeLimit),
      interrupt_(cancel) {}

void StopRules::start(const Film& film) {
    start_ = Interrupt::Clock::now();
    if (film.passes() > 0 || options_.strict) armTimeLimit();
}

void StopRules::armTimeLimit() {
    if (timeLimit_ > 0) interrupt_.setDeadline(fromNow(timeLimit_ - elapsed()));
}

double StopRules::elapsed() const {
    return options_.secondsBefore + secondsSince(start_);
}

std::optional<StopReason> StopRules::afterPass(const Film& film, bool passesLeft) {
    if (interrupt_.cancelled()) return StopReason::Cancelled;
    if (reachedTargetError(film, targetError_)) return StopReason::TargetError;
    if (timeLimit_ > 0 && passesLeft && elapsed() >= timeLimit_) return StopReason::TimeLimit;
    if (film.passes() == 1) armTimeLimit();  // from now on a pass running at the limit is cut
    return std::nullopt;
}

}  // namespace caustic
