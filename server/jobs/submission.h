// A job request (POST /api/jobs), checked before it is queued: the body's shape, the scene (every
// field, meshes loaded from the assets folder only), the settings, and the service's limits. An
// InputError names the JSON path of what is wrong.
#pragma once

#include <string>
#include <vector>

#include "server_config.h"
#include "store/job.h"

namespace caustic::server {

/// The example scenes (name -> file) in a folder: every *.json in it.
std::vector<std::string> exampleSceneNames(const std::filesystem::path& scenesDir);

/// Builds the queued job of a request body: {"scene": <scene object or example name>,
/// "settings": {...}}. The scene's own "settings" come first, the request's override them; the
/// stored settings are complete (every default filled in). Throws InputError.
Job prepareJob(const Json& body, const ServerConfig& config);

}  // namespace caustic::server
