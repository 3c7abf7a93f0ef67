// glTF binaries written in memory for the mesh file tests and the fuzz seeds (glTF 2.0, "GLB File
// Format Specification"): a 12-byte header, the JSON chunk padded with spaces and the BIN chunk
// with zeros, each to a multiple of 4 bytes.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace caustic::testing {

/// Appends the values' bytes as stored: little-endian, as glTF wants, on every machine the
/// renderer builds for (mesh_file_parts.h asserts it).
template <typename T>
void appendBytes(std::string& out, const std::vector<T>& values) {
    out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

inline constexpr uint32_t kGlbJsonChunk = 0x4E4F534A;
inline constexpr uint32_t kGlbBinChunk = 0x004E4942;

/// A .glb of the JSON chunk's text and the BIN chunk (none when `bin` is empty).
inline std::string glbFromChunks(std::string json, std::string bin) {
    json.resize((json.size() + 3) / 4 * 4, ' ');
    bin.resize((bin.size() + 3) / 4 * 4, '\0');
    auto length = uint32_t(12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin.size()));
    std::string out = "glTF";
    appendBytes(out, std::vector<uint32_t>{2, length, uint32_t(json.size()), kGlbJsonChunk});
    out += json;
    if (!bin.empty()) {
        appendBytes(out, std::vector<uint32_t>{uint32_t(bin.size()), kGlbBinChunk});
        out += bin;
    }
    return out;
}

/// A .glb of the JSON document and the BIN chunk (none when `bin` is empty).
inline std::string glbBytes(const nlohmann::json& gltf, std::string bin) {
    return glbFromChunks(gltf.dump(), std::move(bin));
}

struct GlbModel {
    nlohmann::json gltf;
    std::string bin;
    std::string bytes() const { return glbBytes(gltf, bin); }
};

/// The known-answer model: one mesh, the unit square in z = 0 as 4 FLOAT VEC3 positions (accessor
/// 0 in bufferView 0, bytes 0-47) and 2 triangles of UNSIGNED_SHORT indices 0 1 2, 0 2 3
/// (accessor 1 in bufferView 1, bytes 48-59), drawn by two nodes of scene 0: node 0, translated by
/// (0, 0, -5), and its child node 1, translated by (10, 0, 0) and scaled by 2.
inline GlbModel squareGlb() {
    GlbModel m;
    appendBytes(m.bin, std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
    appendBytes(m.bin, std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
    m.gltf = nlohmann::json::parse(R"({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "translation": [0, 0, -5], "children": [1]},
                  {"mesh": 0, "translation": [10, 0, 0], "scale": [2, 2, 2]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
        "buffers": [{"byteLength": 60}]
    })");
    return m;
}

}  // namespace caustic::testing
