// A material's image inputs in the scene format: "file" in the assets folder, a filter and a
// texture transform (DESIGN.md and docs/scene-format.md, "Textures").
#pragma once

#include <string>

#include "scene/json_reader.h"
#include "scene/scene.h"
#include "textures/texture_slot.h"

namespace caustic {

/// The texture at field `key` of `o` (absent: an empty slot): a file name, or an object with
/// "file", "filter" and "transform" (and, when `normalScale` is given, "scale": the normal map's
/// strength in x and y). Prepares its image in the scene's store, made on first use (or, when
/// options.countMeshesOnly, only checks its size and counts the store's cache for admission).
/// InputError at the field's path for a missing, unreadable or oversized image, a bad value.
TextureSlot readTexture(JsonObject& o, const std::string& key, TextureEncoding encoding,
                        const SceneOptions& options, Scene& scene, float* normalScale = nullptr);

}  // namespace caustic
