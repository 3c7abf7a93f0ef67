// `caustic render`: renders a scene file to images.
#pragma once

#include <string>
#include <vector>

namespace caustic {

/// Runs `caustic render` with the arguments after "render". Returns the process exit code: 0 on
/// success, 1 when the render or an output failed, 2 for bad input or usage.
int runRenderCommand(const std::vector<std::string>& args);

}  // namespace caustic
