// EXT_meshopt_compression: bufferViews whose bytes are meshoptimizer's compressed vertex and index
// streams, decoded by meshoptimizer before tinygltf reads the file (the extension's
// specification: each compressed view names its source range, count, stride, mode and filter; a
// "fallback" buffer may hold no data). The decoded views are rewritten to point into one decoded
// buffer, which the loader serves under kMeshoptDecodedUri.
#pragma once

#include <functional>
#include <string>
#include <string_view>

#include "scene/json_reader.h"
#include "scene/mesh_file_parts.h"

namespace caustic {

/// The name the decoded buffer is read under (no file of a model may have it: it is refused
/// before the model's own files are read, gltf_model.cpp).
inline constexpr const char* kMeshoptDecodedUri = "caustic:meshopt-decoded";
/// The name an emptied fallback buffer is read under: no bytes.
inline constexpr const char* kMeshoptEmptyUri = "caustic:meshopt-empty";
/// The most bytes the compressed views of one file may decode to.
inline constexpr size_t kMaxMeshoptBytes = size_t(512) << 20;

/// Whether the buffer is the extension's fallback (it may have no data and, in a .glb, no uri).
bool isMeshoptFallback(const Json& buffer);

/// Decodes every compressed bufferView of `doc` into `decoded`, rewriting the views to point into
/// it (a buffer of uri kMeshoptDecodedUri, which replaces the fallback buffers, or is appended);
/// `source(b)` gives buffer b's bytes. Returns whether the document changed. Fails naming the
/// bufferView: a range outside its buffer, a count, stride, mode or filter the extension does not
/// allow, data that does not decode, more than kMaxMeshoptBytes decoded.
bool decodeMeshopt(Json& doc, const std::function<std::string_view(size_t buffer)>& source,
                   std::string& decoded, const MeshErrors& errors);

}  // namespace caustic
