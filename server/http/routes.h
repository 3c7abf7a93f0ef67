// The HTTP API's routes (DESIGN.md, "Service"; described by server/http/openapi.json), one file
// per resource. Handlers translate requests into calls of the job service (jobs/job_service.h)
// and its results into responses; the policy is the service's.
#pragma once

#include <atomic>

#include <httplib.h>

#include "http/connection_gate.h"
#include "jobs/asset_service.h"
#include "jobs/job_service.h"
#include "jobs/retention.h"
#include "jobs/worker_pool.h"
#include "server_config.h"
#include "store/farm_store.h"

namespace caustic::server {

struct ApiContext {
    const ServerConfig& config;
    JobService& jobs;
    RenderCounters& counters;
    std::atomic<int>& eventStreams;
    const std::atomic<bool>& stopping;
    const StorageCounters& storage;
    AssetService& assets;
    FarmStore* farm = nullptr;  ///< A store shared with worker processes; null for SQLite.
    const ConnectionCounters& connections;
};

/// Registers every route, the guards (http/guards.h), the error bodies and the static files.
void registerRoutes(httplib::Server& http, ApiContext& api);

/// Scale-out: the workers (GET /api/workers) and re-queueing a job (POST .../requeue).
void registerFarmRoutes(httplib::Server& http, ApiContext& api);
/// The jobs: submit, list, read, follow (Server-Sent Events), images, cancel, delete.
void registerJobRoutes(httplib::Server& http, ApiContext& api);
/// Follows a job as Server-Sent Events until it ends or is deleted (GET /api/jobs/{id}/events).
void streamJobEvents(ApiContext& api, const std::string& id, httplib::Response& res);
/// The uploaded meshes: upload, list, read, delete.
void registerAssetRoutes(httplib::Server& http, ApiContext& api);
/// The example scenes, the settings table and the OpenAPI document.
void registerSceneRoutes(httplib::Server& http, ApiContext& api);
/// /healthz and /metrics.
void registerHealthRoutes(httplib::Server& http, ApiContext& api);

/// An integer query parameter in [lo, hi], `fallback` when absent; answers 400 and returns nothing
/// when it is not one.
std::optional<int64_t> integerParam(const httplib::Request& req, httplib::Response& res,
                                    const char* name, int64_t lo, int64_t hi, int64_t fallback);

/// Answers `status` with `body` as application/json.
inline void sendJson(httplib::Response& res, int status, const Json& body) {
    res.status = status;
    res.set_content(body.dump(), "application/json");
}

}  // namespace caustic::server
