// `caustic serve`: runs the render service (server/) until SIGINT or SIGTERM.
#pragma once

#include "server_config.h"

namespace CLI {
class App;
}

namespace caustic {

/// Adds the `serve` subcommand to `app`: its flags fill `config` (which must outlive parsing),
/// from the defaults, environment and ranges its --help shows.
CLI::App* addServeCommand(CLI::App& app, server::ServerConfig& config);

/// Serves as `config` says. Returns the process exit code: 0 after a clean stop, 1 when it cannot
/// start.
int runServe(const server::ServerConfig& config);

}  // namespace caustic
