#include "store/sqlite/job_store.h"

#include <sqlite3.h>

#include <stdexcept>

#include "store/page.h"
#include "store/sqlite/statement.h"

namespace caustic::server {
using sqlite::exec;
using sqlite::Statement;
using sqlite::Transaction;

namespace {

const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS jobs (
    seq INTEGER PRIMARY KEY AUTOINCREMENT,
    id TEXT NOT NULL UNIQUE,
    state TEXT NOT NULL,
    scene TEXT NOT NULL,
    settings TEXT NOT NULL,
    scene_name TEXT NOT NULL DEFAULT '',
    created_at REAL NOT NULL,
    started_at REAL NOT NULL DEFAULT 0,
    finished_at REAL NOT NULL DEFAULT 0,
    attempt INTEGER NOT NULL DEFAULT 0,
    lease_owner TEXT NOT NULL DEFAULT '',
    lease_expires REAL NOT NULL DEFAULT 0,
    stalled_leases INTEGER NOT NULL DEFAULT 0,
    cancel_requested INTEGER NOT NULL DEFAULT 0,
    progress REAL NOT NULL DEFAULT 0,
    passes_done INTEGER NOT NULL DEFAULT 0,
    passes_total INTEGER NOT NULL DEFAULT 0,
    relative_error REAL,
    eta_seconds REAL NOT NULL DEFAULT -1,
    convergence TEXT NOT NULL DEFAULT '[]',
    stats TEXT NOT NULL DEFAULT 'null',
    error TEXT NOT NULL DEFAULT ''
);
CREATE INDEX IF NOT EXISTS jobs_by_state ON jobs (state, seq);
CREATE TABLE IF NOT EXISTS idempotency (
    key TEXT PRIMARY KEY,
    job_id TEXT NOT NULL,
    request_hash TEXT NOT NULL,
    status INTEGER NOT NULL,
    body TEXT NOT NULL
);
)sql";

const char* kJobColumns =
    "seq, id, state, scene, settings, scene_name, created_at, started_at, finished_at, attempt, "
    "lease_owner, lease_expires, stalled_leases, cancel_requested, progress, passes_done, "
    "passes_total, relative_error, eta_seconds, convergence, stats, error, priority, preset_choice";

Job readJob(const Statement& s) {
    Job j;
    j.seq = s.integer(0);
    j.id = s.text(1);
    j.state = parseJobState(s.text(2)).value_or(JobState::Failed);
    j.scene = Json::parse(s.text(3));
    j.settings = Json::parse(s.text(4));
    j.sceneName = s.text(5);
    j.createdAt = s.real(6);
    j.startedAt = s.real(7);
    j.finishedAt = s.real(8);
    j.attempt = int(s.integer(9));
    j.leaseOwner = s.text(10);
    j.leaseExpires = s.real(11);
    j.stalledLeases = int(s.integer(12));
    j.cancelRequested = s.integer(13) != 0;
    j.progress = s.real(14);
    j.passesDone = int(s.integer(15));
    j.passesTotal = int(s.integer(16));
    j.relativeError = s.real(17);
    j.etaSeconds = s.real(18);
    j.convergence = Json::parse(s.text(19));
    j.stats = Json::parse(s.text(20));
    j.error = s.text(21);
    j.priority = int(s.integer(22));
    j.presetChoice = Json::parse(s.text(23));
    return j;
}

std::string selectJobs(const std::string& where) {
    return std::string("SELECT ") + kJobColumns + " FROM jobs " + where;
}

}  // namespace

std::string toString(JobState s) {
    switch (s) {
        case JobState::Queued:
            return "queued";
        case JobState::Running:
            return "running";
        case JobState::Succeeded:
            return "succeeded";
        case JobState::Failed:
            return "failed";
        case JobState::Cancelled:
            return "cancelled";
    }
    return "failed";
}

std::optional<JobState> parseJobState(std::string_view s) {
    for (JobState v : {JobState::Queued, JobState::Running, JobState::Succeeded, JobState::Failed,
                       JobState::Cancelled})
        if (toString(v) == s) return v;
    return std::nullopt;
}

SqliteJobStore::SqliteJobStore(const std::filesystem::path& file) {
    if (sqlite3_open_v2(file.c_str(), &db_,
                        SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                        nullptr) != SQLITE_OK) {
        std::string m = db_ ? sqlite3_errmsg(db_) : "out of memory";
        sqlite3_close(db_);
        throw std::runtime_error("cannot open job store " + file.string() + ": " + m);
    }
    sqlite3_busy_timeout(db_, 5000);
    // WAL with synchronous=FULL: a committed transaction survives a crash of the process or of
    // the machine.
    exec(db_, "PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL; PRAGMA foreign_keys=ON;");
    // Space freed by deleted jobs and assets goes back to the file system (reclaimSpace): pages
    // are freed incrementally (set before the first table; an older file keeps its mode), and a
    // write-ahead log that grew with a large upload is cut back after each checkpoint.
    exec(db_, "PRAGMA auto_vacuum=INCREMENTAL; PRAGMA journal_size_limit=16777216;");
    exec(db_, kSchema);
    // Columns added since the first schema, to a file an older version wrote.
    if (!Statement(db_, "SELECT 1 FROM pragma_table_info('jobs') WHERE name = 'priority'").step())
        exec(db_, "ALTER TABLE jobs ADD COLUMN priority INTEGER NOT NULL DEFAULT 0");
    if (!Statement(db_, "SELECT 1 FROM pragma_table_info('jobs') WHERE name = 'preset_choice'")
             .step())
        exec(db_, "ALTER TABLE jobs ADD COLUMN preset_choice TEXT NOT NULL DEFAULT 'null'");
    createAssetSchema();
}

SqliteJobStore::~SqliteJobStore() {
    sqlite3_close(db_);
}

std::optional<StoredResponse> SqliteJobStore::insert(Job& job, const std::string& key,
                                                     const StoredResponse& response) {
    std::lock_guard lock(mutex_);
    Transaction tx(db_);
    if (!key.empty()) {
        Statement existing(
            db_, "SELECT request_hash, status, body, job_id FROM idempotency WHERE key = ?");
        existing.bind(1, key);
        if (existing.step())
            return StoredResponse{existing.text(0), int(existing.integer(1)), existing.text(2),
                                  existing.text(3)};
    }
    Statement ins(db_,
                  "INSERT INTO jobs (id, state, scene, settings, scene_name, created_at, "
                  "priority, preset_choice) VALUES (?, 'queued', ?, ?, ?, ?, ?, ?)");
    ins.bind(1, job.id)
        .bind(2, job.scene.dump())
        .bind(3, job.settings.dump())
        .bind(4, job.sceneName)
        .bind(5, job.createdAt)
        .bind(6, int64_t(job.priority))
        .bind(7, job.presetChoice.dump());
    ins.run();
    job.seq = sqlite3_last_insert_rowid(db_);
    job.state = JobState::Queued;
    holdAssets(job);
    if (!key.empty()) {
        Statement rec(db_,
                      "INSERT INTO idempotency (key, job_id, request_hash, status, body) VALUES "
                      "(?, ?, ?, ?, ?)");
        rec.bind(1, key)
            .bind(2, job.id)
            .bind(3, response.requestHash)
            .bind(4, response.status)
            .bind(5, response.body);
        rec.run();
    }
    tx.commit();
    return std::nullopt;
}

std::optional<StoredResponse> SqliteJobStore::storedResponse(const std::string& key) {
    std::lock_guard lock(mutex_);
    Statement s(db_, "SELECT request_hash, status, body, job_id FROM idempotency WHERE key = ?");
    s.bind(1, key);
    if (!s.step()) return std::nullopt;
    return StoredResponse{s.text(0), int(s.integer(1)), s.text(2), s.text(3)};
}

std::optional<Job> SqliteJobStore::getLocked(const std::string& id) {
    Statement s(db_, selectJobs("WHERE id = ?"));
    s.bind(1, id);
    if (!s.step()) return std::nullopt;
    Job job = readJob(s);
    Statement assets(db_, "SELECT asset_id FROM job_assets WHERE job_id = ? ORDER BY asset_id");
    assets.bind(1, id);
    while (assets.step()) job.assets.push_back(assets.text(0));
    return job;
}

std::optional<Job> SqliteJobStore::get(const std::string& id) {
    std::lock_guard lock(mutex_);
    return getLocked(id);
}

JobPage SqliteJobStore::list(std::optional<JobState> state, int limit,
                             std::optional<int64_t> before) {
    std::lock_guard lock(mutex_);
    Statement s(
        db_, selectJobs("WHERE (?1 = '' OR state = ?1) AND seq < ?2 ORDER BY seq DESC LIMIT ?3"));
    s.bind(1, state ? toString(*state) : std::string())
        .bind(2, before.value_or(INT64_MAX))
        .bind(3, int64_t(limit) + 1);
    JobPage page;
    while (s.step()) page.jobs.push_back(readJob(s));
    page.next = trimPage(page.jobs, limit);
    return page;
}

std::map<JobState, int64_t> SqliteJobStore::countByState() {
    std::lock_guard lock(mutex_);
    std::map<JobState, int64_t> counts;
    for (JobState s : {JobState::Queued, JobState::Running, JobState::Succeeded, JobState::Failed,
                       JobState::Cancelled})
        counts[s] = 0;
    Statement s(db_, "SELECT state, COUNT(*) FROM jobs GROUP BY state");
    while (s.step())
        if (auto state = parseJobState(s.text(0))) counts[*state] = s.integer(1);
    return counts;
}

std::optional<Job> SqliteJobStore::claim(const std::string& owner, double now, double leaseSeconds,
                                         int maxStalledLeases, int maxAttempts) {
    std::lock_guard lock(mutex_);
    Transaction tx(db_);
    // Expired leases: a cancelled request ends the job; a job that stalled too often fails; the
    // rest go back to the queue in their submission order.
    Statement(db_,
              "UPDATE jobs SET state = 'cancelled', finished_at = ?1, lease_owner = '', "
              "error = 'cancelled while its renderer was gone' WHERE state = 'running' AND "
              "lease_expires <= ?1 AND cancel_requested = 1")
        .bind(1, now)
        .run();
    Statement(db_,
              "UPDATE jobs SET state = 'failed', finished_at = ?1, lease_owner = '', "
              "stalled_leases = stalled_leases + 1, error = 'its renderer stopped ' || "
              "(stalled_leases + 1) || ' times in a row before finishing a pass (the lease "
              "expired); it is not retried again' WHERE state = 'running' AND lease_expires <= ?1 "
              "AND stalled_leases + 1 >= ?2")
        .bind(1, now)
        .bind(2, maxStalledLeases)
        .run();
    Statement(db_,
              "UPDATE jobs SET state = 'queued', lease_owner = '', stalled_leases = "
              "stalled_leases + 1 WHERE state = 'running' AND lease_expires <= ?1")
        .bind(1, now)
        .run();
    Statement(
        db_,
        "UPDATE jobs SET state = 'failed', finished_at = ?1, error = 'started ' || attempt || "
        "' times without finishing (its renderer stopped each time); it is not retried "
        "again' WHERE state = 'queued' AND attempt >= ?2")
        .bind(1, now)
        .bind(2, maxAttempts)
        .run();
    Statement pick(
        db_, "SELECT id FROM jobs WHERE state = 'queued' ORDER BY priority DESC, seq LIMIT 1");
    if (!pick.step()) {
        tx.commit();
        return std::nullopt;
    }
    std::string id = pick.text(0);
    Statement(db_,
              "UPDATE jobs SET state = 'running', attempt = attempt + 1, lease_owner = ?2, "
              "lease_expires = ?3, started_at = CASE WHEN started_at = 0 THEN ?4 ELSE started_at "
              "END, eta_seconds = -1 WHERE id = ?1")
        .bind(1, id)
        .bind(2, owner)
        .bind(3, now + leaseSeconds)
        .bind(4, now)
        .run();
    std::optional<Job> job = getLocked(id);
    tx.commit();
    return job;
}

int SqliteJobStore::expireLeasesNotOwnedBy(const std::string& owner, bool blame) {
    std::lock_guard lock(mutex_);
    Transaction tx(db_);
    int n = 0;
    if (!blame)
        n += Statement(db_,
                       "UPDATE jobs SET state = 'queued', lease_owner = '', lease_expires = 0 "
                       "WHERE state = 'running' AND lease_owner <> ? AND cancel_requested = 0")
                 .bind(1, owner)
                 .run();
    n += Statement(db_,
                   "UPDATE jobs SET lease_expires = 0 WHERE state = 'running' AND lease_owner <> ?")
             .bind(1, owner)
             .run();
    tx.commit();
    return n;
}

LeaseStatus SqliteJobStore::heartbeat(const std::string& id, int attempt, double now,
                                      double leaseSeconds) {
    std::lock_guard lock(mutex_);
    Statement s(db_,
                "UPDATE jobs SET lease_expires = ?3 WHERE id = ?1 AND attempt = ?2 AND state = "
                "'running' RETURNING cancel_requested");
    s.bind(1, id).bind(2, attempt).bind(3, now + leaseSeconds);
    if (!s.step()) return LeaseStatus::Lost;
    LeaseStatus status = s.integer(0) ? LeaseStatus::CancelRequested : LeaseStatus::Held;
    s.run();
    return status;
}

bool SqliteJobStore::recordPass(const std::string& id, int attempt, double progress, int passesDone,
                                int passesTotal, double relativeError, double etaSeconds,
                                const Json& convergencePoint) {
    std::lock_guard lock(mutex_);
    return Statement(db_,
                     "UPDATE jobs SET progress = ?3, passes_done = ?4, passes_total = ?5, "
                     "relative_error = ?6, eta_seconds = ?7, stalled_leases = 0, convergence = "
                     "json_insert(convergence, '$[#]', json(?8)) WHERE id = ?1 AND attempt = ?2 "
                     "AND state = 'running'")
               .bind(1, id)
               .bind(2, attempt)
               .bind(3, progress)
               .bind(4, passesDone)
               .bind(5, passesTotal)
               .bind(6, relativeError)
               .bind(7, etaSeconds)
               .bind(8, convergencePoint.dump())
               .run() == 1;
}

bool SqliteJobStore::finish(const std::string& id, int attempt, JobState state, const Json& stats,
                            const std::string& error, double now) {
    std::lock_guard lock(mutex_);
    return Statement(db_,
                     "UPDATE jobs SET state = ?3, stats = ?4, error = ?5, finished_at = ?6, "
                     "lease_owner = '', eta_seconds = 0, progress = CASE WHEN ?3 = 'succeeded' "
                     "THEN 1 ELSE progress END WHERE id = ?1 AND attempt = ?2 AND state = "
                     "'running'")
               .bind(1, id)
               .bind(2, attempt)
               .bind(3, toString(state))
               .bind(4, stats.dump())
               .bind(5, error)
               .bind(6, now)
               .run() == 1;
}

std::optional<Job> SqliteJobStore::cancel(const std::string& id, double now) {
    std::lock_guard lock(mutex_);
    Transaction tx(db_);
    Statement(db_,
              "UPDATE jobs SET state = 'cancelled', finished_at = ?2, error = 'cancelled before "
              "it started' WHERE id = ?1 AND state = 'queued'")
        .bind(1, id)
        .bind(2, now)
        .run();
    Statement(db_, "UPDATE jobs SET cancel_requested = 1 WHERE id = ?1 AND state = 'running'")
        .bind(1, id)
        .run();
    std::optional<Job> job = getLocked(id);
    tx.commit();
    return job;
}

bool SqliteJobStore::remove(const std::string& id) {
    std::lock_guard lock(mutex_);
    Transaction tx(db_);
    Statement(db_, "DELETE FROM idempotency WHERE job_id = ?").bind(1, id).run();
    Statement(db_, "DELETE FROM job_assets WHERE job_id = ?").bind(1, id).run();
    int n = Statement(db_, "DELETE FROM jobs WHERE id = ?").bind(1, id).run();
    tx.commit();
    return n == 1;
}

std::vector<ExpiredJob> SqliteJobStore::expiredJobs(double finishedBefore, int64_t keepNewest) {
    std::lock_guard lock(mutex_);
    // Ranks the finished jobs newest first (window functions: SQLite 3.25).
    Statement s(db_,
                "SELECT id, finished_at < ?1 FROM (SELECT id, seq, finished_at, ROW_NUMBER() OVER "
                "(ORDER BY finished_at DESC, seq DESC) AS newer FROM jobs WHERE state IN "
                "('succeeded', 'failed', 'cancelled')) WHERE finished_at < ?1 OR newer > ?2 "
                "ORDER BY finished_at, seq");
    s.bind(1, finishedBefore).bind(2, keepNewest < 0 ? INT64_MAX : keepNewest);
    std::vector<ExpiredJob> expired;
    while (s.step()) expired.push_back({s.text(0), s.integer(1) != 0});
    return expired;
}

void SqliteJobStore::reclaimSpace() {
    std::lock_guard lock(mutex_);
    exec(db_, "PRAGMA incremental_vacuum; PRAGMA wal_checkpoint(TRUNCATE);");
}

}  // namespace caustic::server
