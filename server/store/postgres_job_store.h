// The scale-out job store: the same tables and lease protocol as SqliteJobStore on a PostgreSQL
// server, which any number of processes share. Claims take the oldest queued job with
// `FOR UPDATE SKIP LOCKED`, so concurrent claimers never wait for each other nor get the same job;
// every lease holder's write is fenced by attempt as on SQLite. The schema is versioned
// (schema_migrations) and brought up to date when a store is opened.
//
// Thread-safe: one connection behind a mutex, every operation one short transaction (retried
// after a deadlock, a serialization failure, or a connection that broke before the commit).
#pragma once

#include <memory>
#include <mutex>
#include <string>

#include "store/farm_store.h"
#include "store/job_store.h"
#include "store/task.h"

namespace caustic::server {

namespace postgres {
struct Connection;
}

class PostgresJobStore final : public JobStore, public FarmStore {
public:
    /// Connects (`conninfo`: a libpq connection string or postgresql:// URI) and applies the
    /// schema migrations this program knows that the database lacks. Throws std::runtime_error
    /// when it cannot connect, or when the database's schema is newer than this program's.
    /// Connects and migrates the schema; waits up to `waitSeconds` for a database that does not
    /// answer yet (then throws std::runtime_error).
    explicit PostgresJobStore(const std::string& conninfo, double waitSeconds = 0);
    ~PostgresJobStore() override;
    PostgresJobStore(const PostgresJobStore&) = delete;
    PostgresJobStore& operator=(const PostgresJobStore&) = delete;

    /// The schema version this program writes (the highest migration it knows).
    static int schemaVersion();

    std::optional<StoredResponse> insert(Job& job, const std::string& key,
                                         const StoredResponse& response) override;
    std::optional<StoredResponse> storedResponse(const std::string& key) override;
    std::optional<Job> get(const std::string& id) override;
    JobPage list(std::optional<JobState> state, int limit, std::optional<int64_t> before) override;
    std::map<JobState, int64_t> countByState() override;
    std::optional<Job> claim(const std::string& owner, double now, double leaseSeconds,
                             int maxStalledLeases, int maxAttempts) override;
    /// As on SQLite. Only for a store no other process uses: on a shared server the other
    /// owners' leases are live.
    int expireLeasesNotOwnedBy(const std::string& owner, bool blame) override;
    LeaseStatus heartbeat(const std::string& id, int attempt, double now,
                          double leaseSeconds) override;
    bool recordPass(const std::string& id, int attempt, double progress, int passesDone,
                    int passesTotal, double relativeError, double etaSeconds,
                    const Json& convergencePoint) override;
    bool finish(const std::string& id, int attempt, JobState state, const Json& stats,
                const std::string& error, double now) override;
    std::optional<Job> cancel(const std::string& id, double now) override;
    bool remove(const std::string& id) override;
    std::vector<ExpiredJob> expiredJobs(double finishedBefore, int64_t keepNewest) override;

    // Assets: store/postgres_asset_store.cpp.
    AssetInsert insertAsset(Asset& asset, const std::string& bytes, int64_t maxTotalBytes) override;
    std::optional<Asset> getAsset(const std::string& id) override;
    std::shared_ptr<const std::string> assetBytes(const std::string& id) override;
    AssetPage listAssets(int limit, std::optional<int64_t> before) override;
    AssetRemoval removeAsset(const std::string& id) override;
    std::vector<std::string> removeUnusedAssets(double unusedSince) override;
    int64_t assetBytesTotal() override;
    void reclaimSpace() override;

    // Job files (store/postgres_job_files.cpp), for PostgresJobFiles.
    /// Writes a file of attempt `attempt` of a job in one statement; false, writing nothing, when
    /// that is no longer the job's attempt or the job is gone.
    bool putFile(const std::string& id, int attempt, const std::string& name,
                 const std::string& bytes);
    std::optional<std::string> getFile(const std::string& id, const std::string& name);
    /// Removes one file of the job, or every one when `name` is empty.
    void removeFiles(const std::string& id, const std::string& name = {});

    // Scale-out (store/task.h): store/postgres_tasks.cpp. Jobs inserted with taskPasses > 0 get
    // their tasks in insert()'s transaction and are rendered by tasks only (claim() skips them).
    /// Re-queues tasks whose leases expired (failing the jobs of those that stalled too often,
    /// ending cancelled jobs no task renders any more), then leases the next task to `worker`.
    std::optional<ClaimedTask> claimTask(const std::string& worker, double now,
                                         const FarmPolicy& policy);
    /// Held, CancelRequested (the job's cancel was asked), or Lost (another attempt has the task,
    /// or the job no longer needs it: it ended, or reached its target error).
    LeaseStatus heartbeatTask(const Task& task, double now, double leaseSeconds);
    /// Hands in a task's result: merges it into the job's film, and ends the job with its images
    /// when nothing is left to render.
    TaskCommit completeTask(const Task& task, const TaskResult& result, double now);
    /// Gives a task back unrendered (its worker stops, or the job's cancel was asked): queued
    /// again; a cancelled job that no task renders any more ends cancelled.
    void releaseTask(const Task& task, double now);
    /// The render of a task failed on `worker`: the task is queued again, the worker's failures
    /// of the job counted; the job fails when policy.failAfterWorkers workers have failed it.
    /// Returns whether the job failed.
    bool failTask(const Task& task, const std::string& worker, const std::string& error, double now,
                  const FarmPolicy& policy);
    /// Fails the job of a task with `error` (bad input: no other worker would do better).
    bool failJob(const Task& task, const std::string& error, double now);
    std::optional<Job> requeue(const std::string& id) override;
    /// Records that a worker is alive (and what it renders).
    void workerSeen(const WorkerInfo& worker);
    void workerGone(const std::string& id);
    std::vector<WorkerInfo> listWorkers(double seenSince) override;
    int64_t queuedTasks(double now) override;

private:
    std::unique_ptr<postgres::Connection> connection_;
    std::mutex mutex_;
};

}  // namespace caustic::server
