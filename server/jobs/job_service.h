// The job service (DESIGN.md, "Service"): the policy of the job API over the store. It admits jobs
// (jobs/submission.h), gives them ids and time stamps, keeps Idempotency-Key answers, applies the
// queue limit, and cancels and deletes jobs. HTTP route handlers (server/http/) only translate
// requests into its calls and its results into responses. Thread-safe: request threads call it at
// once.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>

#include "jobs/job_events.h"
#include "scene/mesh_counts.h"
#include "server_config.h"
#include "store/job_files.h"
#include "store/job_store.h"

namespace caustic::server {

/// What a submission came to.
struct Submission {
    enum class Outcome {
        Accepted,   ///< Queued now: `response` is the answer to give (and to give again).
        Replayed,   ///< A retry with the same Idempotency-Key and body: the first `response`.
        KeyReused,  ///< The Idempotency-Key came with another body before.
        BadKey,     ///< The Idempotency-Key is too long.
        QueueFull,  ///< Too many jobs wait already.
        DiskFull,   ///< The data folder's disk has less free space than --min-free-mib.
        Invalid,    ///< The body, scene or settings are wrong or over a limit: `pointer`, `detail`.
    };
    Outcome outcome = Outcome::Invalid;
    StoredResponse response;  ///< Accepted, Replayed: status, body and job id.
    std::string detail;       ///< Why it was refused.
    std::string pointer;      ///< Invalid: the JSON path at fault ("" for the whole body).
};

class JobService {
public:
    /// `wakeWorkers` is called once a job is queued.
    JobService(const ServerConfig& config, JobStore& store, const JobFiles& files,
               JobEvents& events, std::function<void()> wakeWorkers);

    /// The answer already given to `key` when a request is a retry (Replayed or KeyReused), or
    /// BadKey; nothing for a new or empty key. Call before parsing the body: a retry is answered
    /// as the first request was, whatever has changed since.
    std::optional<Submission> replay(const std::string& key, const std::string& rawBody);
    /// Admits and queues the job of a parsed body: limits, validation and the memory estimate from
    /// counts (prepareJob), then an id and a time stamp. `respond` makes the answer's body from
    /// the queued job; it is stored under `key` (if any) with the job, atomically.
    Submission submit(const Json& body, const std::string& rawBody, const std::string& key,
                      const std::function<std::string(const Job&)>& respond);

    std::optional<Job> get(const std::string& id) { return store_.get(id); }
    JobPage list(std::optional<JobState> state, int limit, int64_t before) {
        return store_.list(state, limit, before);
    }
    std::map<JobState, int64_t> countByState() { return store_.countByState(); }
    std::optional<LiveProgress> live(const std::string& id) { return events_.live(id); }
    /// Waits until any job changes after version `seen` (updated), or `timeout`; true if one did.
    bool waitForChange(uint64_t& seen, std::chrono::milliseconds timeout) {
        return events_.wait(seen, timeout);
    }
    /// A job's file (image.png, image.exr, preview.png); nothing when it does not exist yet.
    std::optional<std::string> file(const std::string& id, const std::string& name) const {
        return files_.read(id, name);
    }

    /// A job was put back in the queue: wake the workers and the event streams.
    void notifyQueued() {
        wakeWorkers_();
        events_.notify();
    }

    /// Cancels a queued job, or asks a running one's worker to stop. Nothing for an unknown id.
    std::optional<Job> cancel(const std::string& id);
    /// Deletes a job and its files (a running one is asked to stop first). False for an unknown id.
    bool remove(const std::string& id);

    /// Mesh files scanned for their counts so far (one per new or changed file).
    uint64_t meshScans() const { return meshCounts_.scans(); }

private:
    Submission answer(const StoredResponse& stored, const std::string& key,
                      const std::string& hash) const;

    const ServerConfig& config_;
    JobStore& store_;
    const JobFiles& files_;
    JobEvents& events_;
    std::function<void()> wakeWorkers_;
    MeshCountCache meshCounts_;
};

}  // namespace caustic::server
