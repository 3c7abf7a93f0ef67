// The triangles of a glTF scene's meshes, one draw per primitive of each node that has a mesh
// (glTF 2.0, "Meshes"): counted before any is read, since nodes may instance one mesh many times,
// then read with their normals and texture coordinates into world space.
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <string>
#include <vector>

#include "gltf/gltf_nodes.h"
#include "scene/mesh_loader.h"

namespace caustic {

struct GltfDraw {
    NodeInstance instance;
    size_t mesh = 0, primitive = 0;
    int material = -1;  ///< -1: glTF's default material
    uint64_t vertices = 0, triangles = 0;
    bool normals = false, texcoords = false;
};

struct GltfDraws {
    std::vector<GltfDraw> draws;
    /// What was left out, one line each ("mesh 2 (Hair) primitive 0: mode 1 (lines) is not drawn").
    std::vector<std::string> skipped;
    uint64_t vertices = 0, triangles = 0;
};

/// The draws of the nodes: triangle primitives (triangles, strips and fans) with POSITION; points
/// and lines are skipped. Checks every accessor's type and range, and fails once the instanced
/// vertices and triangles pass kMaxGlbElements, before any is read; fails with MeshOverLimit once
/// they pass `maxTriangles` triangles (or kMaxVerticesPerTriangle vertices a triangle).
GltfDraws gltfDraws(const tinygltf::Model& model, const std::vector<NodeInstance>& nodes,
                    const MeshErrors& errors, uint64_t maxTriangles = kMaxGlbElements);

/// A draw's triangles under its node's transform and then `transform`: unit normals when the
/// primitive has NORMAL (else flat), TEXCOORD_0 with `texcoords`. A node whose transform mirrors
/// keeps the file's front sides (its triangles' corners swapped). Fails naming the accessor.
TriangleMesh readDraw(const tinygltf::Model& model, const GltfDraw& draw,
                      const MeshTransform& transform, bool texcoords, const MeshErrors& errors);

/// The draws of the model's default scene joined into one mesh (an uploaded model used as a mesh
/// shape); an attribute one draw lacks is zero there (a zero normal is flat). Fails when nothing
/// is drawn.
TriangleMesh joinedMesh(const tinygltf::Model& model, const MeshTransform& transform,
                        bool texcoords, const MeshErrors& errors,
                        uint64_t maxTriangles = kMaxGlbElements);

}  // namespace caustic
