// glTF accessors read with every byte range checked against its bufferView and that view against
// its buffer (glTF 2.0 specification, "Binary Data Storage"): tinygltf parses them but leaves the
// ranges to its user.
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <vector>

#include "core/math.h"
#include "scene/mesh_file_parts.h"

namespace caustic {

/// What an accessor is read as, and so which types it may have: FLOAT, or the integer types of
/// glTF 2.0's "Meshes" table and KHR_mesh_quantization (normalized or not), for the attributes.
enum class AccessorUse {
    Positions,  ///< VEC3: FLOAT; BYTE, UNSIGNED_BYTE, SHORT, UNSIGNED_SHORT (quantized)
    Normals,    ///< VEC3: FLOAT; normalized BYTE, SHORT (quantized)
    Texcoords,  ///< VEC2: FLOAT; UNSIGNED_BYTE, UNSIGNED_SHORT, BYTE, SHORT
    Indices,    ///< SCALAR: UNSIGNED_BYTE, UNSIGNED_SHORT, UNSIGNED_INT
};

/// Checks that the accessor suits `use` and that all its bytes lie inside its bufferView, and the
/// view inside its buffer; returns its count of elements, reading none.
size_t checkAccessor(const tinygltf::Model& model, int accessor, AccessorUse use,
                     const MeshErrors& errors);

/// The same checks of type alone, for an accessor whose data lies elsewhere (a Draco-compressed
/// primitive's accessors have no bufferView); returns its count.
size_t checkAccessorType(const tinygltf::Model& model, int accessor, AccessorUse use,
                         const MeshErrors& errors);

/// A VEC3 attribute's values (Positions or Normals), integers converted as the accessor's
/// `normalized` says (glTF 2.0, "Animations": c / 127 clamped at -1 for BYTE, c / 255 for
/// UNSIGNED_BYTE, and so on), every coordinate finite. Fails naming the accessor ("accessor 3:
/// ...") or its bufferView.
std::vector<Vec3> readVec3s(const tinygltf::Model& model, int accessor, AccessorUse use,
                            const MeshErrors& errors);
/// A TEXCOORD_n attribute's values, as readVec3s.
std::vector<Vec2> readTexcoords(const tinygltf::Model& model, int accessor,
                                const MeshErrors& errors);

/// A primitive's indices: SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, each <
/// vertexCount
/// ("accessor 3: index 812 is out of range (POSITION has 507
/// vertices)"). Whole triangles are the caller's check: strips and fans take any count.
std::vector<uint32_t> readIndices(const tinygltf::Model& model, int accessor, size_t vertexCount,
                                  const MeshErrors& errors);

}  // namespace caustic
