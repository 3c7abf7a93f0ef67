// Consolidates split jobs' results off the workers' path (store/task.h): a thread of each worker
// process that, woken by this process's hand-ins and every quarter second otherwise, merges the
// results of each running job that has some waiting, at most one batch a second per job (the
// preview's pace) unless the job has nothing left to render. Whichever process takes a job's
// advisory lock first does the batch; the others skip that job.
#pragma once

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "store/postgres/job_store.h"

namespace caustic::server {

class Consolidator {
public:
    /// Starts the thread.
    explicit Consolidator(PostgresJobStore& store, double intervalSeconds = 1.0);
    /// Stops the thread after its batch (a batch cut short rolls back whole).
    ~Consolidator();
    Consolidator(const Consolidator&) = delete;
    Consolidator& operator=(const Consolidator&) = delete;

    /// A result was handed in: look now.
    void wake();
    /// Consolidates every job due once (the thread's round); for tests and benchmarks.
    void round();

private:
    void run();

    PostgresJobStore& store_;
    double intervalSeconds_;
    std::atomic<bool> stopping_{false};
    std::mutex mutex_;
    std::condition_variable wake_;
    bool woken_ = false;
    std::thread thread_;
};

}  // namespace caustic::server
