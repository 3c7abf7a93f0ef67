// A glTF 2.0 document read from memory by tinygltf, with everything it may open or decode
// refused or checked first: a binary .glb holding all its data, or a .gltf whose buffers and
// images are files that a reader, confined to the model's own files, hands over.
#pragma once

#include <tiny_gltf.h>

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scene/mesh_file_parts.h"

namespace caustic {

/// The bytes of the file a .gltf's "uri" names (already percent-decoded, relative to the .gltf),
/// or nothing when there is no such file. It decides what a name may reach: the CLI's reads
/// inside the .gltf's folder, an upload's inside its archive.
using GltfFileReader = std::function<std::optional<std::string>(const std::string& uri)>;

/// Checks a glTF JSON document before tinygltf reads it: at most kMaxGlbJsonBytes, parsed with
/// a depth limit, at most kMaxGlbObjects objects of each kind; without `uris` (a .glb), every
/// buffer and image "uri" is refused, data: included, and only buffer 0 (the BIN chunk) may exist.
void checkGltfJson(std::string_view json, bool uris, const MeshErrors& errors);

/// A .glb (checkGlbContainer, then tinygltf): everything is inside the file.
tinygltf::Model loadGlbModel(std::string_view bytes, const MeshErrors& errors);
/// A .gltf's JSON text, its buffers and images read through `files`.
tinygltf::Model loadGltfModel(std::string_view json, const GltfFileReader& files,
                              const MeshErrors& errors);

/// The encoded bytes (PNG, JPEG, ...) of image `index`: a range of its bufferView, checked against
/// the view and the buffer, or the file its uri named. Fails naming the image.
std::string_view imageBytes(const tinygltf::Model& model, int index, const MeshErrors& errors);

}  // namespace caustic
