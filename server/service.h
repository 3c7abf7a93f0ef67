// The render service: the job store, the workers and the HTTP API (DESIGN.md, "Service"), wired
// together. `caustic serve` makes one and runs it.
#pragma once

#include <atomic>
#include <memory>
#include <string>

#include "http/connection_gate.h"
#include "jobs/asset_service.h"
#include "jobs/job_events.h"
#include "jobs/job_service.h"
#include "jobs/retention.h"
#include "jobs/worker_pool.h"
#include "server_config.h"
#include "store/job_files.h"
#include "store/job_store.h"
#include "store/shared_store.h"

namespace httplib {
class Server;
}

namespace caustic::server {

class RenderService {
public:
    /// Opens the data folder (locking it: one service per folder) and its store, or, with
    /// config.store a PostgreSQL connection string, connects to the shared store (any number of
    /// API and worker processes may). Throws std::runtime_error when it cannot.
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
    /// Opens the embedded store: the data folder's lock, leases left by the last process, the
    /// fault record.
    void openEmbeddedStore();
    /// Connects to a PostgreSQL store shared with other processes.
    void openSharedStore();
    /// Starts (or stops) this process's workers, whichever kind the store has.
    void startWorkers(bool start);
    /// A job was queued: wake an idle worker of this process.
    void wake();

    std::unique_ptr<JobStore> store_;
    std::unique_ptr<JobFiles> files_;
    FarmStore* farm_ = nullptr;       ///< A shared store's tasks and workers (store_ is it).
    std::shared_ptr<void> listener_;  ///< A shared store's listener of changes.
    JobEvents events_;
    RenderCounters counters_;
    std::string owner_;
    std::unique_ptr<Renderers> renderers_;
    StorageCounters storage_;
    std::unique_ptr<RetentionSweeper> retention_;
    std::unique_ptr<JobService> jobs_;
    std::unique_ptr<AssetService> assets_;
    std::unique_ptr<httplib::Server> http_;  ///< Routes and serves requests.
    ConnectionCounters connections_;
    std::unique_ptr<ConnectionGate> gate_;  ///< Accepts connections and hands them to http_.
    std::atomic<int> eventStreams_{0};
    std::atomic<bool> stopping_{false};
};

}  // namespace caustic::server
