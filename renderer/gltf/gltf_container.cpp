// The glTF binary container checked before tinygltf sees it (mesh_file_parts.h): the 12-byte
// header, the chunks, and the JSON chunk's buffers and images, none of which may name a URI.
// Layout from the glTF 2.0 specification, "GLB File Format Specification": a header (magic
// "glTF", version, total length), then chunks (length, type, data), the JSON chunk first and an
// optional BIN chunk second, each starting and ending on a 4-byte boundary; little-endian.
#include <cstdint>
#include <cstring>

#include "gltf/gltf_meshopt.h"
#include "gltf/gltf_model.h"
#include "scene/json_reader.h"
#include "scene/mesh_file.h"
#include "scene/mesh_file_parts.h"

namespace caustic {
namespace {

constexpr uint32_t kHeaderBytes = 12;
constexpr uint32_t kJsonChunk = 0x4E4F534A;  // "JSON"
constexpr uint32_t kBinChunk = 0x004E4942;   // "BIN\0"

uint32_t u32At(std::string_view bytes, size_t offset) {
    uint32_t v;
    std::memcpy(&v, bytes.data() + offset, sizeof v);
    return v;
}

std::string chunkName(size_t index, uint32_t type) {
    std::string kind = type == kJsonChunk  ? "JSON"
                       : type == kBinChunk ? "BIN"
                                           : "type " + std::to_string(type);
    return "chunk " + std::to_string(index) + " (" + kind + ")";
}

// Refuses every "uri" of the named array ("buffers" or "images"): a .glb is accepted only with
// everything in the file. tinygltf would open a relative URI as a file (its default callbacks)
// and decode a data: URI of any size.
void refuseUris(const Json& doc, const char* key, const char* object, const MeshErrors& errors) {
    auto it = doc.find(key);
    if (it == doc.end()) return;
    if (!it->is_array()) errors.fail(std::string("\"") + key + "\" is not an array");
    for (size_t i = 0; i < it->size(); ++i) {
        const Json& o = (*it)[i];
        std::string at = std::string(object) + " " + std::to_string(i) + ": ";
        if (!o.is_object()) errors.fail(at + "is not an object");
        auto uri = o.find("uri");
        if (uri == o.end()) continue;
        std::string text = uri->is_string() ? uri->get<std::string>() : uri->dump();
        bool data = text.rfind("data:", 0) == 0;
        errors.fail(at + "has " +
                    (data ? "a data: uri" : "the uri \"" + text.substr(0, 60) + "\"") +
                    "; only a .glb with everything in its BIN chunk is accepted (no URIs)");
    }
}

}  // namespace

Json checkGlbContainer(std::string_view bytes, const MeshErrors& errors) {
    // Header.
    if (bytes.empty()) errors.fail("the file is empty");
    if (bytes.substr(0, 4) != std::string_view("glTF").substr(0, std::min<size_t>(4, bytes.size())))
        errors.fail("not a glTF binary (a .glb starts with \"glTF\")");
    if (bytes.size() < kHeaderBytes)
        errors.fail("truncated: " + std::to_string(bytes.size()) +
                    " bytes, and the GLB header alone has 12");
    if (uint32_t version = u32At(bytes, 4); version != 2)
        errors.fail("glTF binary version " + std::to_string(version) + "; only version 2 is read");
    uint32_t length = u32At(bytes, 8);
    if (length != bytes.size())
        errors.fail((length > bytes.size() ? "truncated: " : "") + std::string("the header says ") +
                    std::to_string(length) + " bytes, the file has " +
                    std::to_string(bytes.size()));

    // Chunks: JSON, then at most one BIN; other types are skipped, as the specification asks.
    std::string_view json;
    size_t index = 0;
    for (size_t offset = kHeaderBytes; offset < length; ++index) {
        if (length - offset < 8)
            errors.fail("chunk " + std::to_string(index) + ": truncated (its 8-byte header)");
        uint32_t size = u32At(bytes, offset), type = u32At(bytes, offset + 4);
        std::string at = chunkName(index, type) + ": ";
        if (size > length - offset - 8)
            errors.fail(at + "truncated: " + std::to_string(size) + " bytes announced, " +
                        std::to_string(length - offset - 8) + " left");
        if (size % 4 != 0)
            errors.fail(at + "its length " + std::to_string(size) + " is not a multiple of 4");
        if ((index == 0) != (type == kJsonChunk) || (index != 1 && type == kBinChunk))
            errors.fail(at + "a .glb has its JSON chunk first and at most one BIN chunk, second");
        if (index == 0) json = bytes.substr(offset + 8, size);
        offset += 8 + size_t(size);
    }
    if (index == 0) errors.fail("chunk 0: missing (a .glb has a JSON chunk)");

    return checkGltfJson(json, false, errors);
}

std::string_view glbBinChunk(std::string_view glb) {
    const uint32_t json = u32At(glb, kHeaderBytes);
    const size_t bin = kHeaderBytes + 8 + size_t(json);
    if (glb.size() < bin + 8 || u32At(glb, bin + 4) != kBinChunk) return {};
    return glb.substr(bin + 8, u32At(glb, bin));
}

std::string withJsonChunk(std::string_view glb, std::string json) {
    json.resize((json.size() + 3) / 4 * 4, ' ');
    const uint32_t oldJson = u32At(glb, kHeaderBytes);
    const std::string_view rest = glb.substr(kHeaderBytes + 8 + oldJson);
    std::string out(glb.substr(0, kHeaderBytes));
    const uint32_t length = uint32_t(kHeaderBytes + 8 + json.size() + rest.size());
    std::memcpy(out.data() + 8, &length, 4);
    const uint32_t chunk[2] = {uint32_t(json.size()), kJsonChunk};
    out.append(reinterpret_cast<const char*>(chunk), sizeof chunk);
    out += json;
    out.append(rest);
    return out;
}

Json checkGltfJson(std::string_view json, bool uris, const MeshErrors& errors) {
    // Bounded, since tinygltf keeps each node, accessor or mesh in a few hundred bytes (3 bytes
    // of JSON, "{},", would make 450 of memory: a 64 MB file 10 GB), and parsed with a depth
    // limit, since tinygltf reads "extras" recursively.
    const std::string at = uris ? "the JSON: " : "chunk 0 (JSON): ";
    if (json.size() > kMaxGlbJsonBytes)
        errors.fail(at + std::to_string(json.size()) + " bytes; at most " +
                    std::to_string(kMaxGlbJsonBytes) + " are read (the mesh data goes in " +
                    (uris ? "buffers)" : "the BIN chunk)"));
    std::optional<Json> doc = tryParseJson(std::string(json));
    if (!doc || !doc->is_object())
        errors.fail(at + "not a JSON object of at most " + std::to_string(kMaxJsonDepth) +
                    " levels");
    for (const auto& [key, value] : doc->items())
        if (value.is_array() && value.size() > kMaxGlbObjects)
            errors.fail(at + std::to_string(value.size()) + " " + key + "; at most " +
                        std::to_string(kMaxGlbObjects) + " of each are read");
    if (uris) return std::move(*doc);
    refuseUris(*doc, "buffers", "buffer", errors);
    refuseUris(*doc, "images", "image", errors);
    // Only the first buffer may stand for the BIN chunk ("GLB-stored Buffer"); others may be
    // EXT_meshopt_compression's fallbacks, which hold no data.
    if (auto buffers = doc->find("buffers"); buffers != doc->end())
        for (size_t b = 1; b < buffers->size(); ++b)
            if (!isMeshoptFallback((*buffers)[b]))
                errors.fail("buffer " + std::to_string(b) +
                            ": a .glb without URIs holds one buffer, its BIN chunk");
    return std::move(*doc);
}

}  // namespace caustic
