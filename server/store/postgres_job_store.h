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

#include "store/job_store.h"

namespace caustic::server {

namespace postgres {
struct Connection;
}

class PostgresJobStore final : public JobStore {
public:
    /// Connects (`conninfo`: a libpq connection string or postgresql:// URI) and applies the
    /// schema migrations this program knows that the database lacks. Throws std::runtime_error
    /// when it cannot connect, or when the database's schema is newer than this program's.
    explicit PostgresJobStore(const std::string& conninfo);
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

private:
    std::unique_ptr<postgres::Connection> connection_;
    std::mutex mutex_;
};

}  // namespace caustic::server
