// `caustic render`: renders a scene file to images.
#pragma once

#include "render_options.h"

namespace caustic {

/// Renders as `options` say. Returns the process exit code: 0 on success, 1 when an output could
/// not be written, 2 for a bad scene or setting (one line on stderr naming the file and JSON path).
int runRender(const RenderOptions& options);

}  // namespace caustic
