// The image's size: the scene camera's, unless the render settings `width` and `height` override
// it (the CLI's --width and --height, a job's settings).
#pragma once

#include <string>

#include "render/settings.h"
#include "scene/scene.h"

namespace caustic {

/// Gives the scene's camera the size the settings ask for, and the settings the size rendered, so
/// that both name it. A side of 0 keeps the camera's, unless only the other side is given: then it
/// follows the camera's aspect ratio (rounded, at least 1 pixel). Throws InputError at
/// `path`/width or `path`/height when the size is outside `limits` (SceneOptions::maxResolution,
/// maxPixels). Call it after parseSettings and before anything reads the camera's size.
void applyResolution(Scene& scene, RenderSettings& settings, const SceneOptions& limits,
                     const std::string& path = "/settings");

}  // namespace caustic
