// Workers: threads that claim jobs from the store with a lease, render them (never on a request
// thread), checkpoint the film after every pass, and write the images. A heartbeat thread per
// render renews the lease and carries cancellation; a worker that loses its lease stops and
// writes nothing more (the store fences its writes by attempt anyway).
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "jobs/clock.h"
#include "jobs/job_events.h"
#include "jobs/lease_keeper.h"
#include "jobs/renderers.h"
#include "server_config.h"
#include "store/job_files.h"
#include "store/job_store.h"
#include "textures/texture_store.h"

namespace caustic::server {

/// Counters for /metrics.
struct RenderCounters {
    std::atomic<uint64_t> rays{0};
    std::atomic<uint64_t> passes{0};
    std::atomic<double> renderSeconds{0};
    std::atomic<double> lastRaysPerSecond{0};
};

class WorkerPool final : public Renderers {
public:
    WorkerPool(const ServerConfig& config, JobStore& store, const JobFiles& files,
               JobEvents& events, RenderCounters& counters, std::string owner);
    ~WorkerPool() override;

    void start() override;
    /// Stops claiming, cancels running renders (their jobs go back to the queue when their
    /// leases expire, or at the next start-up) and joins the threads.
    void stop() override;
    /// A job was queued: wake an idle worker.
    void wake() override;

private:
    /// How an attempt ended.
    struct Outcome {
        JobState state = JobState::Failed;
        std::string error;
        Json stats;
    };

    void run();
    void renderJob(const Job& job);
    Outcome renderLeased(const Job& job, LeaseKeeper& lease);

    const ServerConfig& config_;
    JobStore& store_;
    const JobFiles& files_;
    JobEvents& events_;
    RenderCounters& counters_;
    std::string owner_;
    std::vector<std::thread> threads_;
    std::atomic<bool> stopping_{false};
    std::mutex mutex_;
    std::condition_variable wake_;
    /// The image textures of every render here, through one bounded cache.
    std::shared_ptr<TextureStore> textures_ =
        std::make_shared<TextureStore>(TextureStore::Options{});
};

}  // namespace caustic::server
