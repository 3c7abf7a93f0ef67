// The parts of parseMeshBytes (mesh_file.h), one file each: the strict OBJ line pass that runs
// before tinyobjloader, and the glTF binary reader around tinygltf.
#pragma once

#include <bit>
#include <string>
#include <string_view>

#include "scene/mesh_file.h"
#include "scene/mesh_loader.h"

namespace caustic {

// glTF binary data is little-endian, and read here as stored.
static_assert(std::endian::native == std::endian::little);

/// Where a mesh file's errors go: InputError at `path`, "<name>: <what>" ("<what>" alone for an
/// empty name).
struct MeshErrors {
    const std::string& name;
    const std::string& path;
    [[noreturn]] void fail(const std::string& what) const;
    /// The same as a MeshOverLimit.
    [[noreturn]] void overLimit(const std::string& what) const;
};

/// Checks OBJ text line by line before tinyobjloader reads it, which reports few errors and reads
/// a bad number as 0: a `v` line needs 3 or more finite numbers; an `f` line needs 3 or more
/// corners whose vertex index (a negative one counts back from the vertices so far) names a vertex
/// defined above it; control bytes are binary data; a last line cut mid-statement is a truncated
/// file. Lines end at "\n", "\r\n" or a lone "\r", as tinyobjloader reads them. Fails with "line N:
/// ...", "the file is empty" or "has no faces (no triangles)". A face has at most
/// kMaxObjFaceCorners corners, and the faces make at most `maxTriangles` triangles (n - 2 each);
/// vertices, normals and texture coordinates are each at most kMaxVerticesPerTriangle times that.
void checkObjLines(std::string_view bytes, const MeshErrors& errors, uint64_t maxTriangles);

/// Reads a glTF 2.0 binary (.glb) or a .zip of a .gltf from memory as one mesh; see
/// parseMeshBytes.
TriangleMesh parseGltf(std::string_view bytes, MeshFormat format, const MeshTransform& transform,
                       bool texcoords, const MeshErrors& errors, uint64_t maxTriangles);

}  // namespace caustic
