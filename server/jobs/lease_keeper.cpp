#include "jobs/lease_keeper.h"

#include <chrono>

#include "jobs/clock.h"

namespace caustic::server {

using SteadyClock = std::chrono::steady_clock;

LeaseKeeper::LeaseKeeper(JobStore& store, const ServerConfig& config, std::string id, int attempt,
                         const std::atomic<bool>& stopping)
    : LeaseKeeper([&store, id = std::move(id), attempt, lease = config.leaseSeconds](
                      double now) { return store.heartbeat(id, attempt, now, lease); },
                  config.leaseSeconds, stopping) {}

LeaseKeeper::LeaseKeeper(std::function<LeaseStatus(double now)> beat, double leaseSeconds,
                         const std::atomic<bool>& stopping)
    : beat_(std::move(beat)),
      leaseSeconds_(leaseSeconds),
      stopping_(stopping),
      thread_([this] { run(); }) {}

LeaseKeeper::~LeaseKeeper() {
    done_ = true;
    thread_.join();
}

void LeaseKeeper::run() {
    const auto period = std::chrono::duration<double>(std::min(1.0, leaseSeconds_ / 4));
    auto last = SteadyClock::now();
    while (!done_) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        if (stopping_) cancel = true;
        if (SteadyClock::now() - last < period) continue;
        last = SteadyClock::now();
        LeaseStatus s = LeaseStatus::Held;
        try {
            s = beat_(unixNow());
        } catch (const std::exception&) {
            continue;  // the store is busy: try again at the next beat
        }
        if (s == LeaseStatus::Lost) lost = true;
        if (s != LeaseStatus::Held) cancel = true;
    }
}

}  // namespace caustic::server
