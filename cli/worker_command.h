// `caustic worker`: renders tasks of a PostgreSQL store's jobs (server/farm/) until SIGINT or
// SIGTERM; no HTTP. Run any number, on any machine that reaches the database.
#pragma once

#include "server_config.h"

namespace CLI {
class App;
}

namespace caustic {

/// Adds the `worker` subcommand to `app`; its flags fill `config`.
CLI::App* addWorkerCommand(CLI::App& app, server::ServerConfig& config);

/// Renders as `config` says. Returns 0 after a clean stop, 1 when it cannot start.
int runWorker(const server::ServerConfig& config);

}  // namespace caustic
