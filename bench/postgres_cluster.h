// A throwaway PostgreSQL 15 cluster for the scale-out benchmarks (queue_overhead, farm_sim):
// tests/support/postgres.sh on 127.0.0.1 with fsync off, removed when the object goes.
#pragma once

#include <unistd.h>

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace caustic::bench {

// A throwaway PostgreSQL cluster (tests/support/postgres.sh), stopped by the destructor, or by
// the script's watcher if this process is killed.
class PostgresCluster {
public:
    PostgresCluster()
        : folder_(std::filesystem::temp_directory_path() /
                  ("caustic-bench-pg-" + std::to_string(getpid()))) {
        const std::string command = "bash '" + script() + "' start '" + folder_.string() +
                                    "' --watch " + std::to_string(getpid());
        FILE* out = popen(command.c_str(), "r");
        if (!out) throw std::runtime_error("cannot run " + command);
        char buffer[512];
        while (std::fgets(buffer, sizeof buffer, out)) url_ += buffer;
        if (pclose(out) != 0 || url_.empty())
            throw std::runtime_error("the PostgreSQL cluster did not start: " + command);
        while (!url_.empty() && std::isspace(static_cast<unsigned char>(url_.back())))
            url_.pop_back();
    }
    ~PostgresCluster() {
        const std::string command = "bash '" + script() + "' stop '" + folder_.string() + "'";
        if (std::system(command.c_str()) != 0)
            std::fprintf(stderr, "could not stop the PostgreSQL cluster in %s\n", folder_.c_str());
    }
    PostgresCluster(const PostgresCluster&) = delete;
    PostgresCluster& operator=(const PostgresCluster&) = delete;
    const std::string& url() const { return url_; }

private:
    static std::string script() { return CAUSTIC_SOURCE_DIR "/tests/support/postgres.sh"; }
    std::filesystem::path folder_;
    std::string url_;
};

/// Whether tests/support/postgres.sh can start a cluster here.
inline bool haveServerBinaries() {
    return access("/usr/lib/postgresql/15/bin/initdb", X_OK) == 0;
}

}  // namespace caustic::bench
