// What only the embedded store does: opening a file an older version of Caustic wrote.
#include <gtest/gtest.h>

#include <sqlite3.h>

#include "store/sqlite/job_store.h"
#include "support/temp_dir.h"

namespace caustic::server {
namespace {

TEST(SqliteJobStore, OpensAFileWrittenBeforeJobsHadPriorities) {
    testing::TempDir dir;
    const auto file = dir.path() / "jobs.sqlite3";
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(file.c_str(), &db), SQLITE_OK);
    // The jobs table of issue 13's release, and one queued job in it.
    ASSERT_EQ(sqlite3_exec(db, R"sql(
CREATE TABLE jobs (
    seq INTEGER PRIMARY KEY AUTOINCREMENT, id TEXT NOT NULL UNIQUE, state TEXT NOT NULL,
    scene TEXT NOT NULL, settings TEXT NOT NULL, scene_name TEXT NOT NULL DEFAULT '',
    created_at REAL NOT NULL, started_at REAL NOT NULL DEFAULT 0,
    finished_at REAL NOT NULL DEFAULT 0, attempt INTEGER NOT NULL DEFAULT 0,
    lease_owner TEXT NOT NULL DEFAULT '', lease_expires REAL NOT NULL DEFAULT 0,
    stalled_leases INTEGER NOT NULL DEFAULT 0, cancel_requested INTEGER NOT NULL DEFAULT 0,
    progress REAL NOT NULL DEFAULT 0, passes_done INTEGER NOT NULL DEFAULT 0,
    passes_total INTEGER NOT NULL DEFAULT 0, relative_error REAL,
    eta_seconds REAL NOT NULL DEFAULT -1, convergence TEXT NOT NULL DEFAULT '[]',
    stats TEXT NOT NULL DEFAULT 'null', error TEXT NOT NULL DEFAULT '');
INSERT INTO jobs (id, state, scene, settings, created_at) VALUES ('old', 'queued', '{}', '{}', 1);
)sql",
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(db);

    SqliteJobStore store(file);
    std::optional<Job> old = store.get("old");
    ASSERT_TRUE(old);
    EXPECT_EQ(old->priority, 0);
    Job urgent;
    urgent.id = "urgent";
    urgent.scene = urgent.settings = Json::object();
    urgent.priority = 1;
    store.insert(urgent, {}, {});
    EXPECT_EQ(store.claim("w", 10, 10, 3, 100)->id, "urgent");
    EXPECT_EQ(store.claim("w", 10, 10, 3, 100)->id, "old");
}

}  // namespace
}  // namespace caustic::server
