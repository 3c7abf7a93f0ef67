// `caustic serve`: runs the render service (server/) until SIGINT or SIGTERM.
#pragma once

#include <string>
#include <vector>

namespace caustic {

/// Returns the process exit code: 0 after a clean stop, 2 for bad usage, 1 when it cannot start.
int runServeCommand(const std::vector<std::string>& args);

}  // namespace caustic
