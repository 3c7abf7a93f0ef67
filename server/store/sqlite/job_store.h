// The embedded job store: one SQLite file in the data folder (WAL journal, so readers do not wait
// for the writer). One connection behind a mutex: every operation is a short transaction.
#pragma once

#include <filesystem>
#include <mutex>

#include "store/job_store.h"

struct sqlite3;

namespace caustic::server {

class SqliteJobStore final : public JobStore {
public:
    /// Opens (creating if needed) the database file. Throws std::runtime_error on failure.
    explicit SqliteJobStore(const std::filesystem::path& file);
    ~SqliteJobStore() override;
    SqliteJobStore(const SqliteJobStore&) = delete;
    SqliteJobStore& operator=(const SqliteJobStore&) = delete;

    std::optional<StoredResponse> insert(Job& job, const std::string& key,
                                         const StoredResponse& response) override;
    std::optional<StoredResponse> storedResponse(const std::string& key) override;
    std::optional<Job> get(const std::string& id) override;
    JobPage list(std::optional<JobState> state, int limit, std::optional<int64_t> before) override;
    std::map<JobState, int64_t> countByState() override;
    std::optional<Job> claim(const std::string& owner, double now, double leaseSeconds,
                             int maxStalledLeases, int maxAttempts) override;
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

    // Assets: store/sqlite/asset_store.cpp.
    AssetInsert insertAsset(Asset& asset, const std::string& bytes, int64_t maxTotalBytes) override;
    std::optional<Asset> getAsset(const std::string& id) override;
    std::shared_ptr<const std::string> assetBytes(const std::string& id) override;
    AssetPage listAssets(int limit, std::optional<int64_t> before) override;
    AssetRemoval removeAsset(const std::string& id) override;
    std::vector<std::string> removeUnusedAssets(double unusedSince) override;
    int64_t assetBytesTotal() override;
    void reclaimSpace() override;

private:
    std::optional<Job> getLocked(const std::string& id);
    /// Creates the asset tables (if needed).
    void createAssetSchema();
    /// Records that `job` uses its assets; throws AssetMissing. Inside insert()'s transaction.
    void holdAssets(const Job& job);

    sqlite3* db_ = nullptr;
    std::mutex mutex_;
};

}  // namespace caustic::server
