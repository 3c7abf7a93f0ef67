// A job request (POST /api/jobs), checked before it is queued: the body's shape, the scene (every
// field; mesh files found in the assets folder only and counted, never loaded), the settings, the
// service's limits and the memory estimate from counts (render/memory_estimate.h). Nothing here
// builds an accelerator, traces a photon or parses a mesh: the worker's render checks memory
// again from what it builds. An InputError names the JSON path of what is wrong.
#pragma once

#include <string>
#include <vector>

#include "scene/mesh_counts.h"
#include "scene/scene.h"
#include "server_config.h"
#include "store/job.h"

namespace caustic::server {

/// The example scenes (name -> file) in a folder: every *.json in it.
std::vector<std::string> exampleSceneNames(const std::filesystem::path& scenesDir);

/// Builds the queued job of a request body: {"scene": <scene object or example name>,
/// "settings": {...}}. The scene's own "settings" come first, the request's override them; the
/// stored settings are complete (every default filled in). Throws InputError. Scans each mesh
/// file for its counts; thread-safe.
Job prepareJob(const Json& body, const ServerConfig& config);
/// The same, with the counts of mesh files already scanned kept in `meshCounts`, and uploaded
/// meshes ("asset" shapes) found by `assets` (without it, such a shape is an InputError); the
/// job's `assets` lists the ids its scene names.
Job prepareJob(const Json& body, const ServerConfig& config, MeshCountCache& meshCounts,
               const MeshAssetResolver& assets = {});

}  // namespace caustic::server
