// The HTTP API's routes (DESIGN.md, "Service"; described by server/http/openapi.json).
#pragma once

#include <atomic>

#include <httplib.h>

#include "jobs/job_events.h"
#include "jobs/worker_pool.h"
#include "server_config.h"
#include "store/job_files.h"
#include "store/job_store.h"

namespace caustic::server {

struct ApiContext {
    const ServerConfig& config;
    JobStore& store;
    const JobFiles& files;
    JobEvents& events;
    RenderCounters& counters;
    WorkerPool& workers;
    std::atomic<int>& eventStreams;
    const std::atomic<bool>& stopping;
};

/// Registers every route, the bearer-token check, the error bodies and the static files.
void registerRoutes(httplib::Server& http, ApiContext& api);

}  // namespace caustic::server
