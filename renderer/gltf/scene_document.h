// The scene a document describes: Caustic's scene format, or a glTF model with overrides
// ({"gltf": {"asset": id} or {"file": name}, "camera": ..., ...}; docs/gltf.md). What the CLI,
// the service's admission and its workers load a job's scene through.
#pragma once

#include <memory>

#include "gltf/gltf_scene.h"
#include "scene/scene.h"

namespace caustic {

/// Whether the document names a glTF model ("gltf").
bool isModelDocument(const Json& doc);

/// Loads the document. With "gltf": the model from options.resolveMeshAsset ("asset": an uploaded
/// .glb) or options.assetsDir ("file": a .glb or .gltf there), imported (only counted with
/// options.countMeshesOnly), the document's overrides applied; `summary`, when given, receives
/// the import's summary with the camera and environment used and the warnings. InputError at the
/// document's JSON paths, the model's own errors at /gltf/asset or /gltf/file.
std::unique_ptr<Scene> loadSceneDocument(const Json& doc, SceneOptions options,
                                         Json* summary = nullptr);

/// A model already read as a scene: imported (only counted with options.countMeshesOnly), the
/// overrides of `request` applied (gltfSceneWithOverrides, at JSON path ""), loaded. `summary`,
/// when given, receives the import's summary with the camera and environment used and the warnings.
std::unique_ptr<Scene> loadModelScene(const GltfFile& model, const Json& request,
                                      SceneOptions options, const MeshErrors& errors,
                                      Json* summary = nullptr);

}  // namespace caustic
