// KHR_draco_mesh_compression: a primitive whose attributes and indices are one Draco-compressed
// bufferView, decoded by Google's Draco library (the extension's specification: the primitive's
// accessors give the counts and types, the extension the bufferView and each attribute's Draco id).
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <vector>

#include "core/math.h"
#include "scene/mesh_file_parts.h"

namespace caustic {

/// The extension's object on a primitive, or null when the primitive is not compressed.
const tinygltf::Value* dracoExtension(const tinygltf::Primitive& prim);

struct DracoPrimitive {
    std::vector<Vec3> positions, normals;  ///< normals empty without NORMAL
    std::vector<Vec2> texcoords;           ///< empty without TEXCOORD_0 or when not asked for
    std::vector<uint32_t> indices;         ///< three a triangle
};

/// Decodes the primitive's Draco bufferView: POSITION, and NORMAL and (with `texcoords`)
/// TEXCOORD_0 when the extension maps them; each value finite, every count equal to its
/// accessor's. Fails naming the primitive (`at`) when the data does not decode or disagrees.
DracoPrimitive decodeDraco(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                           bool texcoords, const std::string& at, const MeshErrors& errors);

}  // namespace caustic
