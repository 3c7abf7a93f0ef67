// The scene's "lights" entries and its "environment" (scene loader internals; DESIGN.md, "Scene
// format").
#pragma once

#include <string>

#include "core/bounds.h"
#include "scene/scene.h"
#include "scene/scene_frame.h"

namespace caustic {

/// Reads one entry of "lights" (point, spot, directional) at `path` into scene.lights. `bounds`:
/// the scene's geometry, which a directional light sends its photons into.
void readLight(const Json& j, const std::string& path, const Frame& frame, const Bounds3& bounds,
               Scene& scene);

/// Reads "environment" into scene.lights and scene.environment: a constant colour or an
/// equirectangular EXR or HDR image from the assets folder. With options.countMeshesOnly only the
/// image's header is read (its size counts in scene.environmentBytes).
void readEnvironment(const Json& j, const std::string& path, const SceneOptions& options,
                     const Bounds3& bounds, Scene& scene);

}  // namespace caustic
