// Keeps a running job's lease: a thread that renews it a few times per lease period while the job
// renders, and turns what the store says (cancellation asked, lease lost), the server's shutdown,
// and a first pass that outlasts the job's time limit into the render's cancel flag.
#pragma once

#include <atomic>
#include <chrono>
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
    /// Stops renewing (the lease then runs out unless the job is finished).
    ~LeaseKeeper();
    LeaseKeeper(const LeaseKeeper&) = delete;
    LeaseKeeper& operator=(const LeaseKeeper&) = delete;

    /// Cancels the render if it has finished no pass `seconds` from now: a time limit holds
    /// for a first pass too, which the render itself always finishes (render/stopping.h).
    void setFirstPassDeadline(double seconds);
    /// A pass was finished: the first-pass deadline no longer applies.
    void passFinished() { passFinished_ = true; }

    /// The render's cancel flag: set when it must stop, for whichever reason below.
    std::atomic<bool> cancel{false};
    /// The store gave the job to another attempt: write nothing more.
    std::atomic<bool> lost{false};
    /// The first pass outlasted the time limit.
    std::atomic<bool> timedOut{false};

private:
    void run();

    JobStore& store_;
    const ServerConfig& config_;
    std::string id_;
    int attempt_;
    const std::atomic<bool>& stopping_;
    std::atomic<bool> done_{false};
    std::atomic<bool> passFinished_{false};
    std::atomic<int64_t> firstPassDeadlineNs_{INT64_MAX};
    std::thread thread_;
};

}  // namespace caustic::server
