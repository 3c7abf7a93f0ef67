// What `caustic serve` and `caustic worker` share: the options of rendering jobs from a store
// (workers, leases, the scale-out's store and failure rules), and stopping on SIGINT or SIGTERM.
#pragma once

#include <signal.h>

#include <string>

#include "server_config.h"

namespace CLI {
class App;
}

namespace caustic::cli {

/// --workers (from `minWorkers`), --threads, --lease-seconds, --max-stalled-leases,
/// --max-attempts.
void addWorkOptions(CLI::App& app, server::ServerConfig& c, int minWorkers);
/// --store (`required` for a worker) and the scale-out's rules (--task-passes,
/// --block-after-failures, ...).
void addStoreOptions(CLI::App& app, server::ServerConfig& c, bool required);
/// --log-level.
void addLogLevelOption(CLI::App& app, server::ServerConfig& c);

/// A connection string as it may be printed: without its password.
std::string redactedStore(const std::string& store);

/// SIGINT and SIGTERM, taken by one thread with sigwait rather than by a handler (stopping a
/// service is not async-signal-safe). Construct it before any thread starts: it blocks them.
class StopSignals {
public:
    StopSignals();
    /// Waits for one; returns it.
    int wait();
    /// Ends a wait() of `thread` (when the service stopped by itself).
    static void release(pthread_t thread) { pthread_kill(thread, SIGTERM); }

private:
    sigset_t signals_;
};

}  // namespace caustic::cli
