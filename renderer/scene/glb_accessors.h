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

enum class AccessorUse { Positions, Indices };

/// Checks that the accessor suits `use` (POSITION: FLOAT VEC3; indices: SCALAR of UNSIGNED_BYTE,
/// UNSIGNED_SHORT or UNSIGNED_INT, whole triangles) and that all its bytes lie inside its
/// bufferView, and the view inside its buffer; returns its count of elements, reading none.
size_t checkAccessor(const tinygltf::Model& model, int accessor, AccessorUse use,
                     const MeshErrors& errors);

/// A POSITION accessor's points: FLOAT VEC3, every coordinate finite. Fails naming the accessor
/// ("accessor 3: ...") or its bufferView.
std::vector<Vec3> readPositions(const tinygltf::Model& model, int accessor,
                                const MeshErrors& errors);

/// A primitive's indices: SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, a multiple of 3
/// of them, each < vertexCount ("accessor 3: index 812 is out of range (POSITION has 507
/// vertices)").
std::vector<uint32_t> readIndices(const tinygltf::Model& model, int accessor, size_t vertexCount,
                                  const MeshErrors& errors);

}  // namespace caustic
