#include "jobs/job_service.h"

#include <cstdio>
#include <random>

#include "core/error.h"
#include "jobs/asset_service.h"
#include "jobs/submission.h"
#include "jobs/worker_pool.h"
#include "store/disk_space.h"

namespace caustic::server {
namespace {

constexpr size_t kMaxKeyLength = 200;

// 128 random bits as 32 hex digits: ids that no client can guess or collide with.
std::string newJobId() {
    static thread_local std::mt19937_64 rng{std::random_device{}() ^
                                            (uint64_t(std::random_device{}()) << 32)};
    char buf[33];
    std::snprintf(buf, sizeof buf, "%016llx%016llx", (unsigned long long)rng(),
                  (unsigned long long)rng());
    return buf;
}

// FNV-1a, 64 bits: identifies a request body for Idempotency-Key retries.
std::string bodyHash(const std::string& body) {
    uint64_t h = 1469598103934665603ull;
    for (unsigned char c : body) h = (h ^ c) * 1099511628211ull;
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", (unsigned long long)h);
    return buf;
}

Submission refused(Submission::Outcome outcome, std::string detail, std::string pointer = {}) {
    Submission s;
    s.outcome = outcome;
    s.detail = std::move(detail);
    s.pointer = std::move(pointer);
    return s;
}

}  // namespace

JobService::JobService(const ServerConfig& config, JobStore& store, const JobFiles& files,
                       JobEvents& events, std::function<void()> wakeWorkers)
    : config_(config),
      store_(store),
      files_(files),
      events_(events),
      wakeWorkers_(std::move(wakeWorkers)) {}

Submission JobService::answer(const StoredResponse& stored, const std::string& key,
                              const std::string& hash) const {
    if (stored.requestHash != hash)
        return refused(Submission::Outcome::KeyReused,
                       "Idempotency-Key \"" + key + "\" was used with another body");
    Submission s;
    s.outcome = Submission::Outcome::Replayed;
    s.response = stored;
    return s;
}

std::optional<Submission> JobService::replay(const std::string& key, const std::string& rawBody) {
    if (key.size() > kMaxKeyLength)
        return refused(Submission::Outcome::BadKey,
                       "Idempotency-Key is over " + std::to_string(kMaxKeyLength) + " characters");
    if (key.empty()) return std::nullopt;
    std::optional<StoredResponse> stored = store_.storedResponse(key);
    if (!stored) return std::nullopt;
    return answer(*stored, key, bodyHash(rawBody));
}

Submission JobService::submit(const Json& body, const std::string& rawBody, const std::string& key,
                              const std::function<std::string(const Job&)>& respond) {
    // Refused before anything is written: a job needs room for its record, checkpoints and images.
    if (std::optional<std::string> low =
            lowDiskSpace(config_.dataDir, config_.storage.minFreeMiB, 0, "a new job"))
        return refused(Submission::Outcome::DiskFull, *low);
    const int64_t queued = store_.countByState()[JobState::Queued];
    if (queued >= config_.limits.maxQueuedJobs)
        return refused(Submission::Outcome::QueueFull,
                       "the queue is full (" + std::to_string(queued) + " jobs waiting)");
    Job job;
    try {
        job = prepareJob(body, config_, meshCounts_, storedAssets(store_));
    } catch (const InputError& e) {
        return refused(Submission::Outcome::Invalid, e.what(), e.path());
    }
    job.id = newJobId();
    job.createdAt = unixNow();
    const std::string hash = bodyHash(rawBody);
    Submission s;
    s.outcome = Submission::Outcome::Accepted;
    s.response = StoredResponse{hash, 202, respond(job), job.id};
    // A concurrent retry with the same key got in first: answer as it was answered.
    try {
        if (std::optional<StoredResponse> raced = store_.insert(job, key, s.response))
            return answer(*raced, key, hash);
    } catch (const AssetMissing& e) {
        return refused(Submission::Outcome::Invalid,
                       "the asset " + e.id() + " was deleted while the job was admitted", "/scene");
    }
    wakeWorkers_();
    events_.notify();
    return s;
}

std::optional<Job> JobService::cancel(const std::string& id) {
    std::optional<Job> job = store_.cancel(id, unixNow());
    if (job) events_.notify();
    return job;
}

bool JobService::remove(const std::string& id) {
    // A running job is asked to stop first; its fenced writes then change nothing.
    store_.cancel(id, unixNow());
    if (!store_.remove(id)) return false;
    files_.remove(id);
    events_.notify();
    return true;
}

}  // namespace caustic::server
