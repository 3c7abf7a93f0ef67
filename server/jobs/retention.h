// Retention (DESIGN.md, "Service"): a thread that, every --sweep-seconds, removes the finished
// jobs (succeeded, failed, cancelled) that finished more than --keep-days ago or are beyond the
// --max-stored-jobs most recently finished, with their files and idempotency records, and the
// uploaded assets no job has used for --keep-days, and measures the data folder's disk use for
// /metrics. Queued and running jobs are never removed.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>

#include "jobs/job_events.h"
#include "server_config.h"
#include "store/job_files.h"
#include "store/job_store.h"

namespace caustic::server {

/// What retention did and measured, for /metrics.
struct StorageCounters {
    std::atomic<uint64_t> sweeps{0};
    std::atomic<uint64_t> jobsRemovedTooOld{0};     ///< Finished more than --keep-days ago.
    std::atomic<uint64_t> jobsRemovedOverCount{0};  ///< Beyond --max-stored-jobs only.
    std::atomic<uint64_t> assetsRemoved{0};         ///< Unused by any job for --keep-days.
    std::atomic<uint64_t> dataBytes{0};  ///< The data folder's disk use at the last sweep.
};

class RetentionSweeper {
public:
    RetentionSweeper(const ServerConfig& config, JobStore& store, const JobFiles& files,
                     JobEvents& events, StorageCounters& counters);
    ~RetentionSweeper();
    RetentionSweeper(const RetentionSweeper&) = delete;
    RetentionSweeper& operator=(const RetentionSweeper&) = delete;

    /// Starts the thread: a sweep at once, then one every config.storage.sweepSeconds.
    void start();
    /// Stops and joins the thread (a sweep under way finishes first).
    void stop();

    /// One sweep at `now` (Unix seconds): removes what retention says and measures the data
    /// folder. Returns the jobs removed. Errors (a busy or full store) are logged; the next sweep
    /// tries again. Safe to call from any thread, but not from two at once.
    int sweep(double now);

private:
    void run();
    int removeExpiredJobs(double now);
    int removeUnusedAssets(double now);

    const ServerConfig& config_;
    JobStore& store_;
    const JobFiles& files_;
    JobEvents& events_;
    StorageCounters& counters_;
    std::thread thread_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stopping_ = false;
};

}  // namespace caustic::server
