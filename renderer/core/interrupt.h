// A request to stop work in progress, polled by every loop whose length a user controls (tiles,
// pixel samples, camera-path bounces and Whitted branches, photon paths and their bounces), so that
// a cancel or a time limit takes effect mid-pass within a fraction of a second, however deep the
// paths. (Steps whose length the user controls only through the scene's size, such as loading a
// mesh or building an accelerator, are not interrupted.)
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

/// A loop's view of an Interrupt: reads it every Interrupt::kPollPeriod calls of poll(). One per
/// thread (it counts); the Interrupt may be null (never stop).
class InterruptPoller {
public:
    explicit InterruptPoller(const Interrupt* interrupt = nullptr) : interrupt_(interrupt) {}
    /// Whether to stop; reads the interrupt every kPollPeriod calls.
    bool poll() {
        return interrupt_ && ++calls_ % Interrupt::kPollPeriod == 0 && interrupt_->requested();
    }

private:
    const Interrupt* interrupt_;
    uint32_t calls_ = 0;
};

/// Seconds since `t0` on the steady clock.
inline double secondsSince(Interrupt::Clock::time_point t0) {
    return std::chrono::duration<double>(Interrupt::Clock::now() - t0).count();
}

/// Seconds from now as a steady-clock time point.
inline Interrupt::Clock::time_point fromNow(double seconds) {
    return Interrupt::Clock::now() + std::chrono::duration_cast<Interrupt::Clock::duration>(
                                         std::chrono::duration<double>(seconds));
}

}  // namespace caustic
