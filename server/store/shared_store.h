// A store shared with worker processes (store/task.h), opened from ServerConfig::store: the one
// place that knows which shared stores this build has (PostgreSQL: store/postgres/shared_store.cpp;
// without it, store/shared_store_none.cpp refuses).
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "jobs/renderers.h"
#include "jobs/worker_pool.h"
#include "server_config.h"
#include "store/farm_store.h"
#include "store/job_files.h"
#include "store/job_store.h"

namespace caustic::server {

struct SharedStore {
    std::unique_ptr<JobStore> jobs;
    std::unique_ptr<JobFiles> files;
    FarmStore* farm = nullptr;             ///< The tasks and workers (GET /api/workers, requeue).
    std::unique_ptr<Renderers> renderers;  ///< This process's task workers.
    std::shared_ptr<void> listener;        ///< Follows changes made by any process.
};

/// Whether `store` (ServerConfig::store) names a PostgreSQL store.
inline bool isPostgresStore(const std::string& store) {
    return store.starts_with("postgresql://") || store.starts_with("postgres://");
}

/// Connects to config.store; `changed` is called when any process changes a job. Throws
/// std::runtime_error when it cannot, or when this build has no such store.
SharedStore openSharedStore(const ServerConfig& config, RenderCounters& counters,
                            std::function<void()> changed);

}  // namespace caustic::server
