// A throwaway PostgreSQL server for tests (tests/support/postgres.sh): one per test binary,
// started by the first test that asks for it and stopped by a gtest Environment when the binary's
// tests are done (or, if the binary is killed, by the script's watcher once the process is gone).
// Each test gets a database of its own.
#pragma once

#include <unistd.h>

#include <pqxx/pqxx>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace caustic::testing {

class PostgresCluster {
public:
    /// Why no cluster can run here: PostgreSQL's server binaries are not installed (the only
    /// reason a test may skip). Nothing when they are.
    static std::optional<std::string> unavailable() {
        const std::filesystem::path initdb = binaries() / "initdb";
        if (access(initdb.c_str(), X_OK) == 0) return std::nullopt;
        return "PostgreSQL's server binaries are not installed (no " + initdb.string() +
               "): install Debian's postgresql (scripts/install-deps.sh)";
    }

    /// The binary's cluster, started on the first call. Throws when it cannot start.
    static PostgresCluster& shared() {
        static std::string failed;  // a cluster that did not start is not tried again
        if (!failed.empty()) throw std::runtime_error(failed);
        try {
            if (!instance()) instance().reset(new PostgresCluster());
        } catch (const std::exception& e) {
            failed = e.what();
            throw;
        }
        return *instance();
    }
    /// Stops the cluster, if one was started, and removes its folder.
    static void stopShared() { instance().reset(); }

    ~PostgresCluster() {
        admin_.reset();
        std::string command = "bash '" + script() + "' stop '" + folder_.string() + "'";
        if (std::system(command.c_str()) != 0)
            std::fprintf(stderr, "postgres_cluster: could not stop %s\n", folder_.c_str());
    }
    PostgresCluster(const PostgresCluster&) = delete;
    PostgresCluster& operator=(const PostgresCluster&) = delete;

    /// Creates an empty database; returns its connection string.
    std::string createDatabase() {
        const std::string name = "test_" + std::to_string(++databases_);
        pqxx::nontransaction(*admin_).exec("CREATE DATABASE " + name);
        return base_ + name;
    }
    /// Drops a database made by createDatabase(), closing any connection still open to it.
    void dropDatabase(const std::string& conninfo) {
        const std::string name = conninfo.substr(base_.size());
        pqxx::nontransaction(*admin_).exec("DROP DATABASE IF EXISTS " + name + " WITH (FORCE)");
    }

    /// Restarts the server on the same port: `fast` (a clean shutdown) or `immediate` (as a crash);
    /// every open connection breaks.
    void restart(const std::string& mode) {
        admin_.reset();
        const std::string command =
            "bash '" + script() + "' restart '" + folder_.string() + "' " + mode;
        if (std::system(command.c_str()) != 0)
            throw std::runtime_error("the test PostgreSQL did not restart: " + command);
        admin_ = std::make_unique<pqxx::connection>(base_ + "postgres");
    }

private:
    PostgresCluster()
        : folder_(std::filesystem::temp_directory_path() /
                  ("caustic-postgres-" + std::to_string(getpid()))) {
        const std::string command = "bash '" + script() + "' start '" + folder_.string() +
                                    "' --watch " + std::to_string(getpid());
        FILE* out = popen(command.c_str(), "r");
        if (!out) throw std::runtime_error("cannot run " + command);
        std::string url;
        char buffer[512];
        while (std::fgets(buffer, sizeof buffer, out)) url += buffer;
        if (pclose(out) != 0 || url.empty())
            throw std::runtime_error("the test PostgreSQL did not start: " + command);
        while (!url.empty() && (url.back() == '\n' || url.back() == '\r')) url.pop_back();
        const std::string database = "/postgres";
        if (url.size() < database.size() ||
            url.compare(url.size() - database.size(), database.size(), database) != 0)
            throw std::runtime_error("unexpected connection string from postgres.sh: " + url);
        base_ = url.substr(0, url.size() - database.size() + 1);
        admin_ = std::make_unique<pqxx::connection>(url);
    }

    static std::unique_ptr<PostgresCluster>& instance() {
        static std::unique_ptr<PostgresCluster> cluster;
        return cluster;
    }
    static std::filesystem::path binaries() {
        const char* bin = std::getenv("CAUSTIC_PG_BIN");
        return bin ? bin : "/usr/lib/postgresql/15/bin";
    }
    static std::string script() { return CAUSTIC_SOURCE_DIR "/tests/support/postgres.sh"; }

    std::filesystem::path folder_;
    std::string base_;  ///< The connection string without its database name.
    std::unique_ptr<pqxx::connection> admin_;
    int databases_ = 0;
};

/// Stops the binary's cluster after its last test.
class PostgresEnvironment : public ::testing::Environment {
public:
    void TearDown() override { PostgresCluster::stopShared(); }
};

inline ::testing::Environment* const kPostgresEnvironment =
    ::testing::AddGlobalTestEnvironment(new PostgresEnvironment);

}  // namespace caustic::testing
