// The job stores the store's tests run against (tests/server/job_store_test.cpp, a typed suite):
// each backend makes an empty store for a test, opens it again (a restart), and removes it.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <random>
#include <string>

#include "store/sqlite/job_store.h"
#ifdef CAUSTIC_HAS_POSTGRES
#include "store/postgres/job_store.h"
#include "support/postgres_cluster.h"
#endif

namespace caustic::testing {

/// A SQLite file in a fresh temporary folder.
class SqliteBackend {
public:
    static constexpr const char* kName = "Sqlite";
    /// Why this backend cannot run here: never.
    static std::optional<std::string> unavailable() { return std::nullopt; }
    void create() {
        dir_ = std::filesystem::temp_directory_path() /
               ("caustic-store-" + std::to_string(std::random_device{}()));
        std::filesystem::create_directories(dir_);
    }
    std::unique_ptr<server::JobStore> open() {
        return std::make_unique<server::SqliteJobStore>(dir_ / "jobs.sqlite3");
    }
    void destroy() { std::filesystem::remove_all(dir_); }

private:
    std::filesystem::path dir_;
};

#ifdef CAUSTIC_HAS_POSTGRES
/// A fresh database in the test binary's throwaway PostgreSQL (support/postgres_cluster.h).
class PostgresBackend {
public:
    static constexpr const char* kName = "Postgres";
    static std::optional<std::string> unavailable() { return PostgresCluster::unavailable(); }
    void create() { conninfo_ = PostgresCluster::shared().createDatabase(); }
    std::unique_ptr<server::JobStore> open() {
        return std::make_unique<server::PostgresJobStore>(conninfo_);
    }
    void destroy() {
        if (!conninfo_.empty()) PostgresCluster::shared().dropDatabase(conninfo_);
    }
    const std::string& conninfo() const { return conninfo_; }

private:
    std::string conninfo_;
};
#endif

}  // namespace caustic::testing
