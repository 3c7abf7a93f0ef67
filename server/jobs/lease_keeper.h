// Keeps a running job's (or task's) lease: heartbeats a few times per lease period on a thread of
// their own while the job renders, and a watch that turns what the store says (cancellation
// asked, lease lost), the server's shutdown, and a lease that must have run out into the render's
// cancel flag. The watch does not wait for the heartbeats: a worker cut off from its store, whose
// heartbeat hangs or fails, stops rendering once its lease must have expired (the last renewal's
// answer plus the lease), before another worker can have claimed the task.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "server_config.h"
#include "store/job_store.h"

namespace caustic::server {

class LeaseKeeper {
public:
    /// Starts renewing the lease of attempt `attempt` of job `id`. `stopping` is the server's
    /// shutdown flag; it must outlive the keeper.
    LeaseKeeper(JobStore& store, const ServerConfig& config, std::string id, int attempt,
                const std::atomic<bool>& stopping);
    /// Renews a lease of `leaseSeconds`, granted just before, by calling `beat(now)`, which must
    /// own what it uses: a heartbeat that hangs past the keeper's end is left to finish alone.
    LeaseKeeper(std::function<LeaseStatus(double now)> beat, double leaseSeconds,
                const std::atomic<bool>& stopping);
    /// Stops renewing (the lease then runs out unless the job is finished).
    ~LeaseKeeper();
    LeaseKeeper(const LeaseKeeper&) = delete;
    LeaseKeeper& operator=(const LeaseKeeper&) = delete;

    /// The render's cancel flag: set when it must stop, for whichever reason below.
    std::atomic<bool> cancel{false};
    /// The store gave the job to another attempt, or the lease ran out: write nothing more.
    std::atomic<bool> lost{false};

private:
    struct Beats;  // the heartbeats' thread and what it learns, shared with it

    void watch();

    double leaseSeconds_;
    const std::atomic<bool>& stopping_;
    std::shared_ptr<Beats> beats_;
    std::atomic<bool> done_{false};
    std::thread watch_;
};

}  // namespace caustic::server
