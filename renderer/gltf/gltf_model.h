// A glTF 2.0 document read from memory by tinygltf, with everything it may open or decode
// refused or checked first: a binary .glb holding all its data, or a .gltf whose buffers and
// images are files that a reader, confined to the model's own files, hands over.
#pragma once

#include <tiny_gltf.h>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scene/json_reader.h"
#include "scene/mesh_file_parts.h"

namespace caustic {

/// The bytes of the file a .gltf's "uri" names (already percent-decoded, relative to the .gltf),
/// or nothing when there is no such file. It decides what a name may reach: the CLI's reads
/// inside the .gltf's folder, an upload's inside its archive.
using GltfFileReader = std::function<std::optional<std::string>(const std::string& uri)>;

/// Checks a glTF JSON document before tinygltf reads it: at most kMaxGlbJsonBytes, parsed with
/// a depth limit, at most kMaxGlbObjects objects of each kind; without `uris` (a .glb), every
/// buffer and image "uri" is refused, data: included, and only buffer 0 (the BIN chunk) may exist.
/// Returns the document.
Json checkGltfJson(std::string_view json, bool uris, const MeshErrors& errors);
/// Checks a .glb's header and chunks and its JSON chunk (checkGltfJson, no URIs), before tinygltf
/// reads it; returns the document.
Json checkGlbContainer(std::string_view bytes, const MeshErrors& errors);

/// A checked .glb's BIN chunk (empty when it has none).
std::string_view glbBinChunk(std::string_view glb);
/// A checked .glb with its JSON chunk replaced by `json` (padded), the other chunks kept.
std::string withJsonChunk(std::string_view glb, std::string json);

/// A glTF file read: tinygltf's model (nodes, meshes, accessors, buffers, images) and the JSON
/// document it came from (materials, cameras, lights and extensions are read from it).
struct GltfFile {
    tinygltf::Model model;
    Json doc;
};

/// A .glb (checkGlbContainer, then tinygltf): everything is inside the file.
GltfFile loadGlbModel(std::string_view bytes, const MeshErrors& errors);
/// A .gltf's JSON text, its buffers and images read through `files`.
GltfFile loadGltfModel(std::string_view json, const GltfFileReader& files,
                       const MeshErrors& errors);

/// Whether a file name ends in .glb or .gltf (any case): a model file rather than a scene.
bool isGltfFileName(const std::string& name);
/// A .glb or .gltf file; a .gltf's buffers and images are files in its own folder (relative
/// URIs that stay inside it).
GltfFile loadGltfPath(const std::filesystem::path& file, const MeshErrors& errors);

/// The encoded bytes (PNG, JPEG, ...) of image `index`: a range of its bufferView, checked against
/// the view and the buffer, or the file its uri named. Fails naming the image.
std::string_view imageBytes(const tinygltf::Model& model, int index, const MeshErrors& errors);

}  // namespace caustic
