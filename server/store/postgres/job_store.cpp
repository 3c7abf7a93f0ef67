#include "store/postgres/job_store.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <spdlog/spdlog.h>

#include "store/page.h"
#include "store/postgres/schema.h"
#include "store/postgres/transaction.h"

namespace caustic::server {
using postgres::getJob;
using postgres::notifyJobs;
using postgres::transact;

namespace {

const char* kJobColumns =
    "seq, id, state, scene, settings, scene_name, created_at, started_at, finished_at, attempt, "
    "lease_owner, lease_expires, stalled_leases, cancel_requested, progress, passes_done, "
    "passes_total, relative_error, eta_seconds, convergence, stats, error, priority, task_passes, "
    "preset_choice";

Job readJob(const pqxx::row& r) {
    Job j;
    j.seq = r[0].as<int64_t>();
    j.id = r[1].as<std::string>();
    j.state = parseJobState(r[2].as<std::string>()).value_or(JobState::Failed);
    j.scene = Json::parse(r[3].as<std::string>());
    j.settings = Json::parse(r[4].as<std::string>());
    j.sceneName = r[5].as<std::string>();
    j.createdAt = r[6].as<double>();
    j.startedAt = r[7].as<double>();
    j.finishedAt = r[8].as<double>();
    j.attempt = r[9].as<int>();
    j.leaseOwner = r[10].as<std::string>();
    j.leaseExpires = r[11].as<double>();
    j.stalledLeases = r[12].as<int>();
    j.cancelRequested = r[13].as<bool>();
    j.progress = r[14].as<double>();
    j.passesDone = r[15].as<int>();
    j.passesTotal = r[16].as<int>();
    j.relativeError = r[17].as<double>();
    j.etaSeconds = r[18].as<double>();
    j.convergence = Json::parse(r[19].as<std::string>());
    j.stats = Json::parse(r[20].as<std::string>());
    j.error = r[21].as<std::string>();
    j.priority = r[22].as<int>();
    j.taskPasses = r[23].as<int>();
    j.presetChoice = Json::parse(r[24].as<std::string>());
    return j;
}

std::string selectJobs(const std::string& where) {
    return std::string("SELECT ") + kJobColumns + " FROM jobs " + where;
}

StoredResponse readResponse(const pqxx::row& r) {
    return StoredResponse{r[0].as<std::string>(), r[1].as<int>(), r[2].as<std::string>(),
                          r[3].as<std::string>()};
}

}  // namespace

namespace postgres {

std::optional<Job> getJob(pqxx::work& tx, const std::string& id, bool lock) {
    pqxx::result rows =
        tx.exec_params(selectJobs(lock ? "WHERE id = $1 FOR UPDATE" : "WHERE id = $1"), id);
    if (rows.empty()) return std::nullopt;
    Job job = readJob(rows[0]);
    for (const pqxx::row& r :
         tx.exec_params("SELECT asset_id FROM job_assets WHERE job_id = $1 ORDER BY asset_id", id))
        job.assets.push_back(r[0].as<std::string>());
    return job;
}

void notifyJobs(pqxx::work& tx) {
    tx.exec("NOTIFY " + std::string(kJobsChannel));
}

}  // namespace postgres

namespace {

// Records that `job` uses its assets (inside insert()'s transaction); throws AssetMissing. The
// update locks each asset's row, so removeAsset() either sees the job or the job sees no asset.
void holdAssets(pqxx::work& tx, const Job& job) {
    for (const std::string& id : job.assets) {
        if (tx.exec_params("UPDATE assets SET last_used_at = GREATEST(last_used_at, $2) WHERE id "
                           "= $1",
                           id, job.createdAt)
                .affected_rows() == 0)
            throw AssetMissing(id);
        tx.exec_params(
            "INSERT INTO job_assets (job_id, asset_id) VALUES ($1, $2) ON CONFLICT DO NOTHING",
            job.id, id);
    }
}

}  // namespace

PostgresJobStore::PostgresJobStore(const std::string& conninfo, double waitSeconds,
                                   const std::string& name)
    : pool_(std::make_unique<postgres::Pool>(conninfo, name)) {
    // Processes started together (a compose project, a cluster's services) may come up before
    // the database accepts connections: try again once a second until the wait is over.
    using Clock = std::chrono::steady_clock;
    const Clock::time_point deadline =
        Clock::now() +
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(waitSeconds));
    for (int attempt = 1;; ++attempt) {
        try {
            postgres::migrate(*pool_->connect());
            if (attempt > 1) spdlog::info("the PostgreSQL store answered (attempt {})", attempt);
            return;
        } catch (const pqxx::broken_connection& e) {
            if (Clock::now() >= deadline) {
                std::ostringstream what;
                what << "cannot connect to the PostgreSQL store";
                if (waitSeconds > 0) what << " in " << waitSeconds << " s (--store-wait)";
                what << ": " << e.what();
                throw std::runtime_error(what.str());
            }
            if (attempt == 1)
                spdlog::info("waiting up to {} s for the PostgreSQL store: {}", waitSeconds,
                             e.what());
            std::this_thread::sleep_until(
                std::min<Clock::time_point>(deadline, Clock::now() + std::chrono::seconds(1)));
        }
    }
}

PostgresJobStore::~PostgresJobStore() = default;

int PostgresJobStore::schemaVersion() {
    return postgres::latestSchemaVersion();
}

std::optional<StoredResponse> PostgresJobStore::insert(Job& job, const std::string& key,
                                                       const StoredResponse& response) {
    return transact(*pool_, [&](pqxx::work& tx) -> std::optional<StoredResponse> {
        if (!key.empty()) {
            // The key first: a concurrent insert of the same key waits here for the other's
            // outcome, then finds its response (or, if that rolled back, takes the key).
            if (tx.exec_params("INSERT INTO idempotency (key, job_id, request_hash, status, "
                               "body) VALUES ($1, $2, $3, $4, $5) ON CONFLICT (key) DO NOTHING",
                               key, job.id, response.requestHash, response.status, response.body)
                    .affected_rows() == 0)
                return readResponse(tx.exec_params1(
                    "SELECT request_hash, status, body, job_id FROM idempotency WHERE key = $1",
                    key));
        }
        job.seq =
            tx.exec_params1(
                  "INSERT INTO jobs (id, state, scene, settings, scene_name, created_at, "
                  "priority, task_passes, passes_total, preset_choice) VALUES ($1, 'queued', $2, "
                  "$3, $4, $5, $6, $7, $8, $9) RETURNING seq",
                  job.id, job.scene.dump(), job.settings.dump(), job.sceneName, job.createdAt,
                  job.priority, job.taskPasses, job.passesTotal, job.presetChoice.dump())[0]
                .as<int64_t>();
        job.state = JobState::Queued;
        holdAssets(tx, job);
        if (job.taskPasses > 0 && job.passesTotal > 0)
            tx.exec_params(
                "INSERT INTO tasks (job_id, first_pass, last_pass) SELECT $1, f, LEAST(f + $2, "
                "$3) FROM generate_series(0, $3 - 1, $2) AS f",
                job.id, job.taskPasses, job.passesTotal);
        notifyJobs(tx);
        return std::nullopt;
    });
}

std::optional<StoredResponse> PostgresJobStore::storedResponse(const std::string& key) {
    return transact(*pool_, [&](pqxx::work& tx) -> std::optional<StoredResponse> {
        pqxx::result r = tx.exec_params(
            "SELECT request_hash, status, body, job_id FROM idempotency WHERE key = $1", key);
        if (r.empty()) return std::nullopt;
        return readResponse(r[0]);
    });
}

std::optional<Job> PostgresJobStore::get(const std::string& id) {
    return transact(*pool_, [&](pqxx::work& tx) { return getJob(tx, id); });
}

JobPage PostgresJobStore::list(std::optional<JobState> state, int limit,
                               std::optional<int64_t> before) {
    return transact(*pool_, [&](pqxx::work& tx) {
        JobPage page;
        for (const pqxx::row& r : tx.exec_params(
                 selectJobs(
                     "WHERE ($1 = '' OR state = $1) AND seq < $2 ORDER BY seq DESC LIMIT $3"),
                 state ? toString(*state) : std::string(), before.value_or(INT64_MAX),
                 int64_t(limit) + 1))
            page.jobs.push_back(readJob(r));
        page.next = trimPage(page.jobs, limit);
        return page;
    });
}

std::map<JobState, int64_t> PostgresJobStore::countByState() {
    return transact(*pool_, [&](pqxx::work& tx) {
        std::map<JobState, int64_t> counts;
        for (JobState s : {JobState::Queued, JobState::Running, JobState::Succeeded,
                           JobState::Failed, JobState::Cancelled})
            counts[s] = 0;
        for (const pqxx::row& r : tx.exec("SELECT state, COUNT(*) FROM jobs GROUP BY state"))
            if (auto state = parseJobState(r[0].as<std::string>()))
                counts[*state] = r[1].as<int64_t>();
        return counts;
    });
}

std::optional<Job> PostgresJobStore::claim(const std::string& owner, double now,
                                           double leaseSeconds, int maxStalledLeases,
                                           int maxAttempts) {
    // Rows another transaction has locked (a claimer, a heartbeat) are skipped, never waited for:
    // whoever holds them settles them, or the next claim does.
    const std::string expired =
        "seq IN (SELECT seq FROM jobs WHERE state = 'running' AND lease_expires <= $1 ";
    return transact(*pool_, [&](pqxx::work& tx) -> std::optional<Job> {
        // Expired leases: a cancelled request ends the job; a job that stalled too often fails;
        // the rest go back to the queue in their submission order.
        tx.exec_params(
            "UPDATE jobs SET state = 'cancelled', finished_at = $1, lease_owner = '', "
            "error = 'cancelled while its renderer was gone' WHERE " +
                expired + "AND cancel_requested FOR UPDATE SKIP LOCKED)",
            now);
        tx.exec_params(
            "UPDATE jobs SET state = 'failed', finished_at = $1, lease_owner = '', "
            "stalled_leases = stalled_leases + 1, error = 'its renderer stopped ' || "
            "(stalled_leases + 1) || ' times in a row before finishing a pass (the "
            "lease expired); it is not retried again' WHERE " +
                expired + "AND stalled_leases + 1 >= $2 FOR UPDATE SKIP LOCKED)",
            now, maxStalledLeases);
        tx.exec_params(
            "UPDATE jobs SET state = 'queued', lease_owner = '', stalled_leases = "
            "stalled_leases + 1 WHERE " +
                expired + "FOR UPDATE SKIP LOCKED)",
            now);
        tx.exec_params(
            "UPDATE jobs SET state = 'failed', finished_at = $1, error = 'started ' || "
            "attempt || ' times without finishing (its renderer stopped each time); "
            "it is not retried again' WHERE seq IN (SELECT seq FROM jobs WHERE state = "
            "'queued' AND attempt >= $2 FOR UPDATE SKIP LOCKED)",
            now, maxAttempts);
        pqxx::result pick = tx.exec(
            "SELECT id FROM jobs WHERE state = 'queued' AND task_passes = 0 ORDER BY priority "
            "DESC, "
            "seq LIMIT 1 "
            "FOR UPDATE SKIP LOCKED");
        if (pick.empty()) return std::nullopt;
        const std::string id = pick[0][0].as<std::string>();
        tx.exec_params(
            "UPDATE jobs SET state = 'running', attempt = attempt + 1, lease_owner = "
            "$2, lease_expires = $3, started_at = CASE WHEN started_at = 0 THEN $4 "
            "ELSE started_at END, eta_seconds = -1 WHERE id = $1",
            id, owner, now + leaseSeconds, now);
        return getJob(tx, id);
    });
}

int PostgresJobStore::expireLeasesNotOwnedBy(const std::string& owner, bool blame) {
    return transact(*pool_, [&](pqxx::work& tx) {
        int n = 0;
        if (!blame)
            n += int(tx.exec_params("UPDATE jobs SET state = 'queued', lease_owner = '', "
                                    "lease_expires = 0 WHERE state = 'running' AND lease_owner "
                                    "<> $1 AND NOT cancel_requested",
                                    owner)
                         .affected_rows());
        n += int(tx.exec_params("UPDATE jobs SET lease_expires = 0 WHERE state = 'running' AND "
                                "lease_owner <> $1",
                                owner)
                     .affected_rows());
        return n;
    });
}

LeaseStatus PostgresJobStore::heartbeat(const std::string& id, int attempt, double now,
                                        double leaseSeconds) {
    return transact(*pool_, [&](pqxx::work& tx) {
        pqxx::result r = tx.exec_params(
            "UPDATE jobs SET lease_expires = $3 WHERE id = $1 AND attempt = $2 AND state = "
            "'running' RETURNING cancel_requested",
            id, attempt, now + leaseSeconds);
        if (r.empty()) return LeaseStatus::Lost;
        return r[0][0].as<bool>() ? LeaseStatus::CancelRequested : LeaseStatus::Held;
    });
}

bool PostgresJobStore::recordPass(const std::string& id, int attempt, double progress,
                                  int passesDone, int passesTotal, double relativeError,
                                  double etaSeconds, const Json& convergencePoint) {
    return transact(*pool_, [&](pqxx::work& tx) {
        notifyJobs(tx);
        return tx.exec_params(
                     "UPDATE jobs SET progress = $3, passes_done = $4, passes_total = $5, "
                     "relative_error = $6, eta_seconds = $7, stalled_leases = 0, "
                     "convergence = convergence || jsonb_build_array($8::jsonb) WHERE "
                     "id = $1 AND attempt = $2 AND state = 'running'",
                     id, attempt, progress, passesDone, passesTotal, relativeError, etaSeconds,
                     convergencePoint.dump())
                   .affected_rows() == 1;
    });
}

bool PostgresJobStore::finish(const std::string& id, int attempt, JobState state, const Json& stats,
                              const std::string& error, double now) {
    return transact(*pool_, [&](pqxx::work& tx) {
        notifyJobs(tx);
        return tx.exec_params(
                     "UPDATE jobs SET state = $3, stats = $4, error = $5, finished_at = "
                     "$6, lease_owner = '', eta_seconds = 0, progress = CASE WHEN $3 = "
                     "'succeeded' THEN 1 ELSE progress END WHERE id = $1 AND attempt = "
                     "$2 AND state = 'running'",
                     id, attempt, toString(state), stats.dump(), error, now)
                   .affected_rows() == 1;
    });
}

std::optional<Job> PostgresJobStore::cancel(const std::string& id, double now) {
    return transact(*pool_, [&](pqxx::work& tx) {
        tx.exec_params(
            "UPDATE jobs SET state = 'cancelled', finished_at = $2, error = 'cancelled "
            "before it started' WHERE id = $1 AND state = 'queued'",
            id, now);
        tx.exec_params(
            "UPDATE jobs SET cancel_requested = TRUE WHERE id = $1 AND state = 'running'", id);
        // A split job that no task renders right now ends at once.
        tx.exec_params(
            "UPDATE jobs SET state = 'cancelled', finished_at = $2, error = 'cancelled' WHERE id "
            "= $1 AND state = 'running' AND task_passes > 0 AND NOT EXISTS (SELECT 1 FROM tasks "
            "WHERE job_id = $1 AND state = 'running')",
            id, now);
        notifyJobs(tx);
        return getJob(tx, id);
    });
}

bool PostgresJobStore::remove(const std::string& id) {
    return transact(*pool_, [&](pqxx::work& tx) {
        tx.exec_params("DELETE FROM idempotency WHERE job_id = $1", id);
        tx.exec_params("DELETE FROM job_assets WHERE job_id = $1", id);
        notifyJobs(tx);
        return tx.exec_params("DELETE FROM jobs WHERE id = $1", id).affected_rows() == 1;
    });
}

std::vector<ExpiredJob> PostgresJobStore::expiredJobs(double finishedBefore, int64_t keepNewest) {
    return transact(*pool_, [&](pqxx::work& tx) {
        std::vector<ExpiredJob> expired;
        for (const pqxx::row& r : tx.exec_params(
                 "SELECT id, finished_at < $1 FROM (SELECT id, seq, finished_at, ROW_NUMBER() "
                 "OVER (ORDER BY finished_at DESC, seq DESC) AS newer FROM jobs WHERE state IN "
                 "('succeeded', 'failed', 'cancelled')) AS finished WHERE finished_at < $1 OR "
                 "newer > $2 ORDER BY finished_at, seq",
                 finishedBefore, keepNewest < 0 ? INT64_MAX : keepNewest))
            expired.push_back({r[0].as<std::string>(), r[1].as<bool>()});
        return expired;
    });
}

}  // namespace caustic::server
