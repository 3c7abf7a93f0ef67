// Tangent frames for normal-mapped meshes that bring none: MikkTSpace (Mikkelsen 2008, "Simulation
// of wrinkled surfaces revisited"), which glTF 2.0 requires and in which Blender and most bakers
// write normal maps.
#pragma once

#include <vector>

#include <glm/vec4.hpp>

#include "scene/mesh_loader.h"

namespace caustic {

/// Per-vertex MikkTSpace tangents of `mesh` (xyz, and the bitangent's sign in w). A vertex that
/// MikkTSpace gives different tangents on different faces (a seam of the texture layout, or a
/// flat-shaded mesh's shared corner) is split, its attributes copied, so that `mesh` changes.
/// Empty for a mesh without texture coordinates (no tangent frame follows from them).
std::vector<glm::vec4> generateTangents(TriangleMesh& mesh);

}  // namespace caustic
