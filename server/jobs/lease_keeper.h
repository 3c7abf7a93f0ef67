// Keeps a running job's (or task's) lease: a thread that renews it a few times per lease period
// while the job renders, and turns what the store says (cancellation asked, lease lost) and the
// server's shutdown into the render's cancel flag.
#pragma once

#include <atomic>
#include <functional>
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
    /// Renews a lease of `leaseSeconds` by calling `beat(now)` (store/task.h's tasks).
    LeaseKeeper(std::function<LeaseStatus(double now)> beat, double leaseSeconds,
                const std::atomic<bool>& stopping);
    /// Stops renewing (the lease then runs out unless the job is finished).
    ~LeaseKeeper();
    LeaseKeeper(const LeaseKeeper&) = delete;
    LeaseKeeper& operator=(const LeaseKeeper&) = delete;

    /// The render's cancel flag: set when it must stop, for whichever reason below.
    std::atomic<bool> cancel{false};
    /// The store gave the job to another attempt: write nothing more.
    std::atomic<bool> lost{false};

private:
    void run();

    std::function<LeaseStatus(double now)> beat_;
    double leaseSeconds_;
    const std::atomic<bool>& stopping_;
    std::atomic<bool> done_{false};
    std::thread thread_;
};

}  // namespace caustic::server
