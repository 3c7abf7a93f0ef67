#include "store/postgres/schema.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace caustic::server::postgres {
namespace {

// Append only: a released migration is never edited, a change is a new one.
struct Migration {
    int version;
    const char* sql;
};

const std::vector<Migration>& migrations() {
    static const std::vector<Migration> all{
        {.version = 1, .sql = R"sql(
CREATE TABLE jobs (
    seq BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
    id TEXT NOT NULL UNIQUE,
    state TEXT NOT NULL,
    scene TEXT NOT NULL,
    settings TEXT NOT NULL,
    scene_name TEXT NOT NULL DEFAULT '',
    created_at DOUBLE PRECISION NOT NULL,
    started_at DOUBLE PRECISION NOT NULL DEFAULT 0,
    finished_at DOUBLE PRECISION NOT NULL DEFAULT 0,
    attempt INTEGER NOT NULL DEFAULT 0,
    lease_owner TEXT NOT NULL DEFAULT '',
    lease_expires DOUBLE PRECISION NOT NULL DEFAULT 0,
    stalled_leases INTEGER NOT NULL DEFAULT 0,
    cancel_requested BOOLEAN NOT NULL DEFAULT FALSE,
    progress DOUBLE PRECISION NOT NULL DEFAULT 0,
    passes_done INTEGER NOT NULL DEFAULT 0,
    passes_total INTEGER NOT NULL DEFAULT 0,
    relative_error DOUBLE PRECISION NOT NULL DEFAULT 'NaN',
    eta_seconds DOUBLE PRECISION NOT NULL DEFAULT -1,
    convergence JSONB NOT NULL DEFAULT '[]',
    stats TEXT NOT NULL DEFAULT 'null',
    error TEXT NOT NULL DEFAULT ''
);
CREATE INDEX jobs_by_state ON jobs (state, seq);
CREATE TABLE idempotency (
    key TEXT PRIMARY KEY,
    job_id TEXT NOT NULL,
    request_hash TEXT NOT NULL,
    status INTEGER NOT NULL,
    body TEXT NOT NULL
);
CREATE INDEX idempotency_by_job ON idempotency (job_id);
CREATE TABLE assets (
    seq BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
    id TEXT NOT NULL UNIQUE,
    format TEXT NOT NULL,
    name TEXT NOT NULL DEFAULT '',
    bytes BIGINT NOT NULL,
    triangles BIGINT NOT NULL,
    vertices BIGINT NOT NULL,
    bounds TEXT NOT NULL,
    created_at DOUBLE PRECISION NOT NULL,
    last_used_at DOUBLE PRECISION NOT NULL,
    data BYTEA NOT NULL
);
CREATE TABLE job_assets (
    job_id TEXT NOT NULL,
    asset_id TEXT NOT NULL,
    PRIMARY KEY (job_id, asset_id)
);
CREATE INDEX job_assets_by_asset ON job_assets (asset_id);
)sql"},
        // Scale-out: tasks (pass ranges of a job), job files (the merged film, previews,
        // images) in the database so that nodes share nothing else, the workers, and which
        // worker failed which job's tasks (store/task.h).
        {.version = 2, .sql = R"sql(
ALTER TABLE jobs ADD COLUMN priority INTEGER NOT NULL DEFAULT 0;
ALTER TABLE jobs ADD COLUMN task_passes INTEGER NOT NULL DEFAULT 0;
CREATE INDEX jobs_by_priority ON jobs (priority DESC, seq) WHERE state IN ('queued', 'running');
CREATE TABLE tasks (
    job_id TEXT NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    first_pass INTEGER NOT NULL,
    last_pass INTEGER NOT NULL,
    state TEXT NOT NULL DEFAULT 'queued',
    attempt INTEGER NOT NULL DEFAULT 0,
    lease_owner TEXT NOT NULL DEFAULT '',
    lease_expires DOUBLE PRECISION NOT NULL DEFAULT 0,
    stalled_leases INTEGER NOT NULL DEFAULT 0,
    passes_done INTEGER NOT NULL DEFAULT 0,
    rays BIGINT NOT NULL DEFAULT 0,
    render_seconds DOUBLE PRECISION NOT NULL DEFAULT 0,
    result BYTEA,
    PRIMARY KEY (job_id, first_pass)
);
CREATE INDEX tasks_by_state ON tasks (state, job_id, first_pass);
CREATE TABLE job_files (
    job_id TEXT NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    name TEXT NOT NULL,
    data BYTEA NOT NULL,
    PRIMARY KEY (job_id, name)
);
CREATE TABLE workers (
    id TEXT PRIMARY KEY,
    host TEXT NOT NULL,
    cores INTEGER NOT NULL,
    threads INTEGER NOT NULL,
    started_at DOUBLE PRECISION NOT NULL,
    last_seen DOUBLE PRECISION NOT NULL,
    job_id TEXT NOT NULL DEFAULT '',
    first_pass INTEGER NOT NULL DEFAULT -1,
    last_pass INTEGER NOT NULL DEFAULT -1,
    tasks_done BIGINT NOT NULL DEFAULT 0,
    tasks_failed BIGINT NOT NULL DEFAULT 0
);
CREATE TABLE task_failures (
    job_id TEXT NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    worker_id TEXT NOT NULL,
    failures INTEGER NOT NULL,
    last_error TEXT NOT NULL,
    PRIMARY KEY (job_id, worker_id)
);
)sql"},
        // Films and pass images are stored as they are: pglz found 39% of a film's exact sums
        // compressible, and each hand-in paid decompressing and recompressing the whole film.
        {.version = 3, .sql = R"sql(
ALTER TABLE job_files ALTER COLUMN data SET STORAGE EXTERNAL;
ALTER TABLE tasks ALTER COLUMN result SET STORAGE EXTERNAL;
)sql"},
        // Hand-ins store their results for consolidation (store/task.h): a result waits in its
        // task's row until a batch merges it (tasks handed in together point at the row that
        // holds their result: result_task); the job's last batch time paces the previews.
        // Results of the earlier design were merged at hand-in (no result kept), except a
        // target error's passes waiting for their turn.
        {.version = 4, .sql = R"sql(
ALTER TABLE tasks ADD COLUMN merged BOOLEAN NOT NULL DEFAULT FALSE;
ALTER TABLE tasks ADD COLUMN result_task INTEGER;
UPDATE tasks SET merged = (state = 'done' AND result IS NULL);
CREATE INDEX tasks_waiting ON tasks (job_id, first_pass) WHERE state = 'done' AND NOT merged;
ALTER TABLE jobs ADD COLUMN consolidated_at DOUBLE PRECISION NOT NULL DEFAULT 0;
)sql"},
        // What a preset chose for the job's scene, and why (render/presets.h: presetChoice).
        {.version = 5, .sql = R"sql(
ALTER TABLE jobs ADD COLUMN preset_choice TEXT NOT NULL DEFAULT 'null';
)sql"},
    };
    return all;
}

// pg_advisory_xact_lock's key for migrations: "caustic" in ASCII.
constexpr int64_t kMigrationLock = 0x63617573746963;

}  // namespace

int latestSchemaVersion() {
    return migrations().back().version;
}

void migrate(pqxx::connection& connection) {
    pqxx::work tx(connection);
    // One process at a time; the others wait here and then find nothing left to do.
    tx.exec_params("SELECT pg_advisory_xact_lock($1)", kMigrationLock);
    tx.exec(
        "CREATE TABLE IF NOT EXISTS schema_migrations (version INTEGER PRIMARY KEY, applied_at "
        "TIMESTAMPTZ NOT NULL DEFAULT now())");
    const int current =
        tx.exec1("SELECT COALESCE(MAX(version), 0) FROM schema_migrations")[0].as<int>();
    if (current > latestSchemaVersion())
        throw std::runtime_error("the PostgreSQL store's schema is version " +
                                 std::to_string(current) + ", newer than this program's " +
                                 std::to_string(latestSchemaVersion()) + ": upgrade Caustic");
    for (const Migration& m : migrations()) {
        if (m.version <= current) continue;
        tx.exec(m.sql);
        tx.exec_params("INSERT INTO schema_migrations (version) VALUES ($1)", m.version);
    }
    tx.commit();
}

}  // namespace caustic::server::postgres
