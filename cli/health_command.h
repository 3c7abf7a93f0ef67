// `caustic health`: asks a running service's /healthz and exits 0 when it answers 200, 1
// otherwise; a container's HEALTHCHECK (docker/Dockerfile) without curl in the image.
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace caustic {

struct HealthOptions {
    std::string url = "http://127.0.0.1:8080/healthz";
    double timeoutSeconds = 5;
};

/// Adds the `health` subcommand to `app`; its flags fill `options`.
CLI::App* addHealthCommand(CLI::App& app, HealthOptions& options);

/// 0 when the service answered 200, 1 otherwise (with the reason on stderr).
int runHealth(const HealthOptions& options);

}  // namespace caustic
