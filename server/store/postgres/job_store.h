// The scale-out job store: the same tables and lease protocol as SqliteJobStore on a PostgreSQL
// server, which any number of processes share. Claims take the oldest queued job with
// `FOR UPDATE SKIP LOCKED`, so concurrent claimers never wait for each other nor get the same job;
// every lease holder's write is fenced by attempt as on SQLite. The schema is versioned
// (schema_migrations) and brought up to date when a store is opened.
//
// Thread-safe: a pool of connections, every operation one short transaction on a connection of its
// own (store/postgres/transaction.h).
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "store/farm_store.h"
#include "store/job_store.h"
#include "store/task.h"

namespace caustic::server {

namespace postgres {
class Pool;
}

class PostgresJobStore final : public JobStore, public FarmStore {
public:
    /// Connects (`conninfo`: a libpq connection string or postgresql:// URI) and applies the
    /// schema migrations this program knows that the database lacks. Throws std::runtime_error
    /// when it cannot connect, or when the database's schema is newer than this program's.
    /// Connects and migrates the schema; waits up to `waitSeconds` for a database that does not
    /// answer yet (then throws std::runtime_error).
    /// `name` is the connections' application_name (pg_stat_activity): the process's role and id.
    explicit PostgresJobStore(const std::string& conninfo, double waitSeconds = 0,
                              const std::string& name = "caustic");
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

    // Assets: store/postgres/asset_store.cpp.
    AssetInsert insertAsset(Asset& asset, const std::string& bytes, int64_t maxTotalBytes) override;
    std::optional<Asset> getAsset(const std::string& id) override;
    std::shared_ptr<const std::string> assetBytes(const std::string& id) override;
    AssetPage listAssets(int limit, std::optional<int64_t> before) override;
    AssetRemoval removeAsset(const std::string& id) override;
    std::vector<std::string> removeUnusedAssets(double unusedSince) override;
    int64_t assetBytesTotal() override;
    void reclaimSpace() override;

    // Job files (store/postgres/job_files.cpp), for PostgresJobFiles.
    /// Writes a file of attempt `attempt` of a job in one statement; false, writing nothing, when
    /// that is no longer the job's attempt or the job is gone.
    bool putFile(const std::string& id, int attempt, const std::string& name,
                 const std::string& bytes);
    std::optional<std::string> getFile(const std::string& id, const std::string& name);
    /// Removes one file of the job, or every one when `name` is empty.
    void removeFiles(const std::string& id, const std::string& name = {});

    // Scale-out (store/task.h): store/postgres/tasks.cpp. Jobs inserted with taskPasses > 0 get
    // their tasks in insert()'s transaction and are rendered by tasks only (claim() skips them).
    /// Re-queues tasks whose leases expired (failing the jobs of those that stalled too often,
    /// ending cancelled jobs no task renders any more), then leases the next task to `worker`.
    /// Of the queued tasks of the highest priority, those of job `prefer` come first (a worker
    /// that holds some of its tasks goes on with it).
    std::optional<ClaimedTask> claimTask(const std::string& worker, const FarmPolicy& policy,
                                         const std::string& prefer = {});
    /// Renews the leases of tasks one worker holds (of one job): Held, CancelRequested (the job's
    /// cancel was asked), or Lost (another attempt has one of them, or the job no longer needs
    /// them: it ended, or reached its target error).
    LeaseStatus heartbeatTasks(const std::vector<Task>& tasks, double leaseSeconds);
    LeaseStatus heartbeatTask(const Task& task, double leaseSeconds) {
        return heartbeatTasks({task}, leaseSeconds);
    }
    /// Hands in tasks of one job and their result (a film of all their passes, or one task's
    /// pass images): stores it for consolidation (Accepted), or, when one of them is no longer
    /// its holder's, nothing (Fenced). A cancelled job whose last running tasks these were ends.
    TaskCommit completeTasks(const std::vector<TaskDone>& tasks, const std::string& result);
    TaskCommit completeTask(const Task& task, const TaskResult& result) {
        return completeTasks({{task, result.passesDone, result.rays, result.renderSeconds}},
                             result.passImages.empty() ? result.film : result.passImages);
    }
    /// Merges the results of job `id` that wait (store/task.h), at most one batch; ends the job
    /// with its images when nothing is left to render. store/postgres/consolidation.cpp.
    Consolidation consolidate(const std::string& id, const ConsolidationLimits& limits = {});
    /// Running split jobs with results waiting whose last batch is `intervalSeconds` old, or
    /// that have no task left to render (their last batch is due at once).
    std::vector<std::string> jobsToConsolidate(double intervalSeconds);
    /// Gives a task back unrendered (its worker stops, or the job's cancel was asked): queued
    /// again; a cancelled job that no task renders any more ends cancelled.
    void releaseTasks(const std::vector<Task>& tasks);
    void releaseTask(const Task& task) { releaseTasks({task}); }
    /// The render of a task failed on `worker`: the task is queued again, the worker's failures
    /// of the job counted; the job fails when policy.failAfterWorkers workers have failed it.
    /// Returns whether the job failed.
    bool failTask(const Task& task, const std::string& worker, const std::string& error,
                  const FarmPolicy& policy);
    /// Fails the job of a task with `error` (bad input: no other worker would do better).
    bool failJob(const Task& task, const std::string& error);
    std::optional<Job> requeue(const std::string& id) override;
    /// Records that a worker is alive (and what it renders), by the database's clock.
    void workerSeen(const WorkerInfo& worker);
    void workerGone(const std::string& id);
    std::vector<WorkerInfo> listWorkers(double aliveSeconds) override;
    int64_t queuedTasks() override;

private:
    std::unique_ptr<postgres::Pool> pool_;
};

}  // namespace caustic::server
