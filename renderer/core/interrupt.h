// A request to stop work in progress, polled by every loop whose length a user controls (tiles,
// camera-path bounces, photon paths and their bounces), so that a cancel or a time limit takes
// effect mid-pass within milliseconds, however deep the paths.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <limits>

namespace caustic {

class Interrupt {
public:
    using Clock = std::chrono::steady_clock;

    /// Stop when *cancel becomes true (the flag must outlive this object); null for never.
    explicit Interrupt(const std::atomic<bool>* cancel = nullptr) : cancel_(cancel) {}

    /// Stop at `deadline` as well (from any thread).
    void setDeadline(Clock::time_point deadline) {
        deadlineNs_.store(deadline.time_since_epoch().count(), std::memory_order_relaxed);
    }

    /// Whether work should stop: cancelled, or past the deadline. Thread-safe; an atomic load,
    /// and a clock read while a deadline is set: cheap enough for every few hundred bounces.
    bool requested() const {
        if (cancel_ && cancel_->load(std::memory_order_relaxed)) return true;
        int64_t deadline = deadlineNs_.load(std::memory_order_relaxed);
        return deadline != kNever && Clock::now().time_since_epoch().count() >= deadline;
    }

    /// Whether the cancel flag (not the deadline) asked to stop.
    bool cancelled() const { return cancel_ && cancel_->load(std::memory_order_relaxed); }

    /// Bounce loops poll every kPollPeriod iterations: a bounce costs about a microsecond.
    static constexpr int kPollPeriod = 256;

private:
    static constexpr int64_t kNever = std::numeric_limits<int64_t>::max();
    const std::atomic<bool>* cancel_;
    std::atomic<int64_t> deadlineNs_{kNever};
};

/// For loops: whether `interrupt` (may be null) asks to stop at iteration i (polled every
/// kPollPeriod iterations).
inline bool interruptedAt(const Interrupt* interrupt, int64_t i) {
    return interrupt && i % Interrupt::kPollPeriod == Interrupt::kPollPeriod - 1 &&
           interrupt->requested();
}

}  // namespace caustic
