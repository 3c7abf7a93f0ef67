#include "jobs/lease_keeper.h"

#include <chrono>
#include <condition_variable>
#include <mutex>

#include <spdlog/spdlog.h>

#include "jobs/clock.h"

namespace caustic::server {

using SteadyClock = std::chrono::steady_clock;

struct LeaseKeeper::Beats {
    std::function<LeaseStatus(double now)> beat;
    std::mutex mutex;
    std::condition_variable stop;
    bool done = false, beating = false;
    /// When the lease must have run out: the last renewal's answer plus the lease.
    SteadyClock::time_point expires;
    std::atomic<bool> cancelRequested{false}, lost{false};
    std::thread thread;

    void run(double leaseSeconds) {
        const auto lease = std::chrono::duration_cast<SteadyClock::duration>(
            std::chrono::duration<double>(leaseSeconds));
        const auto period = std::chrono::duration<double>(std::min(1.0, leaseSeconds / 4));
        std::unique_lock lock(mutex);
        while (true) {
            if (stop.wait_for(lock, period, [this] { return done; })) return;
            beating = true;
            lock.unlock();
            LeaseStatus s = LeaseStatus::Held;
            bool answered = true;
            try {
                s = beat(unixNow());
            } catch (const std::exception&) {
                answered = false;  // the store is out of reach: try again at the next beat
            }
            const auto now = SteadyClock::now();
            lock.lock();
            beating = false;
            if (!answered) continue;
            if (s == LeaseStatus::Held) expires = now + lease;
            if (s == LeaseStatus::Lost) lost = true;
            if (s == LeaseStatus::CancelRequested) cancelRequested = true;
        }
    }
};

LeaseKeeper::LeaseKeeper(JobStore& store, const ServerConfig& config, std::string id, int attempt,
                         const std::atomic<bool>& stopping)
    : LeaseKeeper([&store, id = std::move(id), attempt, lease = config.leaseSeconds](
                      double now) { return store.heartbeat(id, attempt, now, lease); },
                  config.leaseSeconds, stopping) {}

LeaseKeeper::LeaseKeeper(std::function<LeaseStatus(double now)> beat, double leaseSeconds,
                         const std::atomic<bool>& stopping)
    : leaseSeconds_(leaseSeconds), stopping_(stopping), beats_(std::make_shared<Beats>()) {
    beats_->beat = std::move(beat);
    beats_->expires = SteadyClock::now() + std::chrono::duration_cast<SteadyClock::duration>(
                                               std::chrono::duration<double>(leaseSeconds));
    beats_->thread = std::thread([beats = beats_, leaseSeconds] { beats->run(leaseSeconds); });
    watch_ = std::thread([this] { watch(); });
}

LeaseKeeper::~LeaseKeeper() {
    done_ = true;
    watch_.join();
    std::unique_lock lock(beats_->mutex);
    beats_->done = true;
    const bool hung = beats_->beating;
    lock.unlock();
    beats_->stop.notify_all();
    // A heartbeat still waiting for its store finishes alone (it owns what it uses).
    if (hung)
        beats_->thread.detach();
    else
        beats_->thread.join();
}

void LeaseKeeper::watch() {
    while (!done_) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        if (stopping_ || beats_->cancelRequested) cancel = true;
        if (beats_->lost) lost = cancel = true;
        std::lock_guard lock(beats_->mutex);
        if (SteadyClock::now() >= beats_->expires && !lost) {
            spdlog::warn(
                "the lease ran out ({} s without a renewal the store answered): the "
                "render stops",
                leaseSeconds_);
            lost = cancel = true;
        }
    }
}

}  // namespace caustic::server
