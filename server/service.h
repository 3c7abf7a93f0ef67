// The render service: the job store, the workers and the HTTP API (DESIGN.md, "Service"), wired
// together. `caustic serve` makes one and runs it.
#pragma once

#include <atomic>
#include <memory>
#include <string>

#include "jobs/asset_service.h"
#include "jobs/job_events.h"
#include "jobs/job_service.h"
#include "jobs/worker_pool.h"
#include "server_config.h"
#include "store/job_files.h"
#include "store/job_store.h"

namespace httplib {
class Server;
}

namespace caustic::server {

class RenderService {
public:
    /// Opens the data folder (locking it: one service per folder) and its store. Throws
    /// std::runtime_error when it cannot.
    explicit RenderService(ServerConfig config);
    ~RenderService();

    /// Binds the address; returns the port (useful with port 0). Throws when it cannot bind.
    int bind();
    /// Starts the workers and serves until stop(). Blocks.
    void serve();
    /// Stops serving and rendering (from any thread or a signal watcher).
    void stop();

private:
    ServerConfig config_;
    int lockFd_ = -1;
    int faultFd_ = -1;  ///< The fault record, written only when the process dies of a fault.
    std::unique_ptr<JobStore> store_;
    JobFiles files_;
    JobEvents events_;
    RenderCounters counters_;
    std::string owner_;
    std::unique_ptr<WorkerPool> workers_;
    std::unique_ptr<JobService> jobs_;
    std::unique_ptr<AssetService> assets_;
    std::unique_ptr<httplib::Server> http_;
    std::atomic<int> eventStreams_{0};
    std::atomic<bool> stopping_{false};
};

}  // namespace caustic::server
