// A glTF scene's node trees walked with their transforms (glTF 2.0, "Nodes and Hierarchy" and
// "Transformations"), every index and the hierarchy itself checked: one parent a node, no cycle.
#pragma once

#include <tiny_gltf.h>

#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "scene/mesh_file_parts.h"

namespace caustic {

struct NodeInstance {
    size_t node;
    glm::dmat4 world;  ///< The node's global transform: its parents' and its own.
};

/// "node 3", or "node 3 (Wheel)" when it has a name: how messages name glTF objects.
std::string gltfObjectName(const char* kind, size_t index, const std::string& name);

/// Every node reached from the roots of the file's default scene (its "scene", else scene 0, else
/// every parentless node), depth first, each once, with its world transform. Fails naming the
/// node: a child or root that does not exist, a node with two parents, a cycle, a matrix or
/// translation/rotation/scale of the wrong size, a rotation that is no quaternion.
std::vector<NodeInstance> walkNodes(const tinygltf::Model& model, const MeshErrors& errors);

}  // namespace caustic
