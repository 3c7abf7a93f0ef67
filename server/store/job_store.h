// The durable job queue and its lease protocol, one interface over SQLite (embedded default) and
// PostgreSQL (scale-out).
//
// Protocol (DESIGN.md, "Service"). A worker claims the oldest queued job with a lease: the store
// sets it running, increments its `attempt` and records the owner and an expiry time. The holder
// renews the lease by heartbeats, and every write it makes (a finished pass, the outcome) names
// (id, attempt): a write whose attempt is no longer the job's current one changes nothing and
// returns false, so a worker that lost its lease (it stalled, or the store gave the job to
// another) can never overwrite a newer attempt's state. A lease that expires puts the job back in
// the queue; a job whose leases expire `maxStalledLeases` times in a row without finishing a pass
// (it crashes whoever renders it) fails with the reason. Files a job writes go to a temporary name
// and are renamed, and every pass of a render depends only on its index, so that two attempts write
// the same bytes: which one's rename wins does not matter.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "store/asset.h"
#include "store/job.h"

namespace caustic::server {

/// The first response to a request with an Idempotency-Key, kept to be returned on retries.
struct StoredResponse {
    std::string requestHash;  ///< Of the request body: a retry must send the same body.
    int status = 0;
    std::string body;
    std::string jobId;
};

/// What a heartbeat learns.
enum class LeaseStatus { Held, CancelRequested, Lost };

/// A finished job that retention removes (jobs/retention.h), and which rule removes it.
struct ExpiredJob {
    std::string id;
    bool tooOld = false;  ///< Finished before the cutoff; else only beyond the count kept.
};

struct JobPage {
    std::vector<Job> jobs;
    std::optional<int64_t> next;  ///< Cursor (a seq) for the next page, if there is one.
};

/// A job names an asset that is no longer stored (deleted after admission): nothing was inserted.
class AssetMissing : public std::runtime_error {
public:
    explicit AssetMissing(std::string id)
        : std::runtime_error("no asset " + id), id_(std::move(id)) {}
    const std::string& id() const { return id_; }

private:
    std::string id_;
};

class JobStore {
public:
    virtual ~JobStore() = default;

    /// Adds a queued job; assigns job.seq. With `key`, atomically records `response` under it; if
    /// the key is taken (a concurrent retry), adds nothing and returns the stored response. The
    /// job's `assets` are recorded as used by it (and their last use set to its createdAt) in the
    /// same transaction; throws AssetMissing, inserting nothing, when one is no longer stored.
    virtual std::optional<StoredResponse> insert(Job& job, const std::string& key = {},
                                                 const StoredResponse& response = {}) = 0;
    virtual std::optional<StoredResponse> storedResponse(const std::string& key) = 0;

    virtual std::optional<Job> get(const std::string& id) = 0;
    /// Jobs by submission order, newest first, from cursor `before` (a seq; none for the newest).
    virtual JobPage list(std::optional<JobState> state, int limit,
                         std::optional<int64_t> before) = 0;
    virtual std::map<JobState, int64_t> countByState() = 0;

    /// Re-queues (or fails) jobs whose leases expired by `now`, then leases the oldest queued job
    /// to `owner` until now + leaseSeconds. Nothing when the queue is empty. A queued job already
    /// started `maxAttempts` times fails instead: the last guard against a job that takes down
    /// whoever renders it without leaving a fault record (the kernel's out-of-memory kill).
    virtual std::optional<Job> claim(const std::string& owner, double now, double leaseSeconds,
                                     int maxStalledLeases, int maxAttempts) = 0;
    /// Ends every lease not held by `owner` (an embedded store at start-up: the previous
    /// process is gone, and a lock on the data folder proves no other one runs). With `blame`
    /// (that process died of a fault), the leases expire as stalled ones do: claim() counts them
    /// against maxStalledLeases. Without (it was killed or stopped from outside, which says
    /// nothing about the jobs it rendered), the jobs go straight back to the queue with their
    /// stall counts unchanged; those whose cancellation was asked still end cancelled in claim().
    virtual int expireLeasesNotOwnedBy(const std::string& owner, bool blame) = 0;
    virtual LeaseStatus heartbeat(const std::string& id, int attempt, double now,
                                  double leaseSeconds) = 0;
    /// Records a finished pass: progress, the convergence point, and stalledLeases = 0.
    virtual bool recordPass(const std::string& id, int attempt, double progress, int passesDone,
                            int passesTotal, double relativeError, double etaSeconds,
                            const Json& convergencePoint) = 0;
    /// Ends the attempt: state succeeded, failed or cancelled, with stats and the error text.
    virtual bool finish(const std::string& id, int attempt, JobState state, const Json& stats,
                        const std::string& error, double now) = 0;

    /// Cancels a queued job at once; asks a running one's holder to stop (it sees it in its next
    /// heartbeat). Returns the job after the change; nothing for an unknown id.
    virtual std::optional<Job> cancel(const std::string& id, double now) = 0;
    /// Removes a job, its idempotency record and its hold on its assets. False for an unknown id.
    virtual bool remove(const std::string& id) = 0;
    /// Finished jobs (succeeded, failed, cancelled; never a queued or running one) that retention
    /// removes, oldest first, in one query: those that finished before `finishedBefore` (Unix
    /// seconds), and those beyond the `keepNewest` most recently finished (no count limit when
    /// negative).
    virtual std::vector<ExpiredJob> expiredJobs(double finishedBefore, int64_t keepNewest) = 0;

    // Assets (store/asset.h): uploaded meshes, kept in the store itself so that every worker of a
    // scale-out reads the same bytes, each written in one transaction.

    /// Stores an asset and its bytes (asset.seq assigned), unless its id is stored already
    /// (Existing: `asset` becomes the stored one, its last use set to asset.lastUsedAt) or the
    /// stored bytes would pass `maxTotalBytes` (Full). Throws StorageFull when the disk is full.
    virtual AssetInsert insertAsset(Asset& asset, const std::string& bytes,
                                    int64_t maxTotalBytes) = 0;
    virtual std::optional<Asset> getAsset(const std::string& id) = 0;
    /// An asset's file, for rendering; null for an unknown id.
    virtual std::shared_ptr<const std::string> assetBytes(const std::string& id) = 0;
    /// Assets by upload order, newest first, from cursor `before` (a seq; none for the newest).
    virtual AssetPage listAssets(int limit, std::optional<int64_t> before) = 0;
    /// Removes an asset unless a queued or running job uses it (InUse), in one transaction;
    /// finished jobs that used it lose their hold on it.
    virtual AssetRemoval removeAsset(const std::string& id) = 0;
    /// Removes the assets that no job uses whose last use is before `unusedSince` (Unix seconds);
    /// returns their ids. For a retention policy.
    virtual std::vector<std::string> removeUnusedAssets(double unusedSince) = 0;
    /// The bytes of every stored asset together.
    virtual int64_t assetBytesTotal() = 0;
    /// Gives the space of removed rows back to the file system (retention calls it after removing).
    virtual void reclaimSpace() = 0;
};

}  // namespace caustic::server
