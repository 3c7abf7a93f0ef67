// Everything `caustic serve` can be told: where it listens and keeps its data, who may write, how
// it renders, and the limits that protect a small machine (each a command-line flag, see
// cli/serve_command.cpp).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace caustic::server {

/// Limits on what a job may ask, checked before it is queued (422 names the JSON path; 413 for a
/// body over the size, 429 for a full queue).
struct ServiceLimits {
    size_t maxRequestBytes = size_t(8) << 20;
    int maxJsonDepth = 64;
    int maxResolution = 4096;                  ///< Pixels per side.
    int64_t maxPixels = int64_t(2048) * 2048;  ///< width x height.
    int maxSpp = 65536;
    int64_t maxPhotons = 10000000;  ///< photons, caustic_photons, indirect_photons, per pass.
    double maxTimeLimit = 3600;     ///< Seconds; a job that sets none gets this one.
    double maxMemoryMiB = 4096;     ///< Estimated peak; a job's memory_limit is capped by it.
    int maxQueuedJobs = 100;        ///< Queued (not yet running) jobs.
    int maxEventStreams = 64;       ///< Concurrent Server-Sent Events connections.
    // Connections (http/connection_gate.h): what one client may hold, and how slowly it may send.
    int maxConnections = 1024;             ///< Open at once, all clients (503 above).
    int maxConnectionsPerClient = 32;      ///< Open at once from one address; 0 for no limit (429).
    double requestHeadSeconds = 10;        ///< For a request's head, from connect or last response.
    int64_t minBodyBytesPerSecond = 8192;  ///< A body's average rate, after the head's seconds.
    size_t maxAssetBytes = size_t(256) << 20;  ///< One uploaded mesh file (413 above).
    int64_t maxAssetTriangles = 20000000;      ///< One uploaded mesh, as loaded (422 above).
    int64_t maxAssetStorageMiB = 4096;         ///< Every stored asset together (507 above).
    int maxUploads = 4;                        ///< Uploads read and checked at once (429 above).
};

/// What the service keeps and for how long (jobs/retention.h), and the free space it needs on the
/// data folder's disk.
struct StoragePolicy {
    double keepDays = 7;       ///< Finished jobs go this long after finishing; 0 keeps them.
    int maxStoredJobs = 1000;  ///< Finished jobs kept at most, the newest; 0 for no limit.
    double sweepSeconds = 60;  ///< How often retention runs and the folder's use is measured.
    double minFreeMiB = 64;    ///< POST /api/jobs answers 507 with less free space than this.
};

struct ServerConfig {
    std::string host = "127.0.0.1";
    int port = 8080;
    std::filesystem::path dataDir = "data";
    std::filesystem::path assetsDir;  ///< Mesh files resolve inside it only.
    std::filesystem::path scenesDir;  ///< Example scenes, submitted by name.
    std::filesystem::path webDir;     ///< Static files of the web page.
    std::filesystem::path docsDir;    ///< The documentation (docs/), served at /docs/.
    std::string token;  ///< Bearer token for mutating requests; required off loopback.
    /// A PEM certificate (chain) and its private key: with both, the service speaks HTTPS only.
    std::filesystem::path tlsCert, tlsKey;
    bool tls() const { return !tlsCert.empty(); }
    /// Origins ("http://host:port") whose pages may change jobs and read answers (CORS).
    std::vector<std::string> allowedOrigins;
    std::string logLevel = "info";  ///< Of the messages and the access log (server/logging.h).
    std::string accessLog;          ///< A file; "-" for stdout; empty for stderr.
    int workers = 1;                ///< Jobs rendered at once.
    int renderThreads = 0;          ///< Threads per render; 0 for every core.
    double leaseSeconds = 10;
    int maxStalledLeases = 3;
    int maxAttempts = 100;  ///< Starts of one job, whatever stopped them.
    /// The job store: empty for SQLite in the data folder, or a PostgreSQL connection string
    /// (postgresql://...) shared by API and worker processes anywhere (store/task.h).
    std::string store;
    // Scale-out (PostgreSQL only).
    double storeWaitSeconds = 30;  ///< How long a start waits for the PostgreSQL store.
    int taskPasses = 8;            ///< Passes per task of a job that sets no task_passes.
    /// The most render seconds a worker goes on with tasks of one job before it hands them in
    /// as one film (farm/task_workers.h).
    double handInSeconds = 120;
    int blockAfterFailures = 2;  ///< A worker's failed tasks of a job before it skips the job.
    int failAfterWorkers = 3;    ///< Workers that failed a job's tasks before the job fails.
    bool failEveryTask = false;  ///< Test only: this process's workers fail every task.
    ServiceLimits limits;
    StoragePolicy storage;
};

}  // namespace caustic::server
