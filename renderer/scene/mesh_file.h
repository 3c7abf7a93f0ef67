// Mesh files users upload (OBJ, and binary glTF): loaded from memory by the real loaders and
// checked vertex by vertex and index by index, so that a file the service accepts is one it can
// render.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "core/error.h"
#include "core/math.h"
#include "scene/mesh_loader.h"

namespace caustic {

/// An OBJ, a glTF binary, or a .zip holding a .gltf with its buffers and images.
enum class MeshFormat { Obj, Glb, GltfZip };

/// "model/obj" -> Obj, "model/gltf-binary" -> Glb, "application/zip" -> GltfZip (media-type
/// parameters such as "; charset=utf-8" and case ignored); nothing for any other type.
std::optional<MeshFormat> meshFormatOfMediaType(std::string_view mediaType);
const char* mediaTypeOf(
    MeshFormat format);                 ///< "model/obj", "model/gltf-binary", "application/zip"
const char* nameOf(MeshFormat format);  ///< "obj", "glb", "zip"
std::optional<MeshFormat> meshFormatNamed(std::string_view name);  ///< "obj", "glb", "zip"
/// Whether the format is a glTF model (a whole scene): Glb or GltfZip.
inline bool isGltfFormat(MeshFormat format) {
    return format == MeshFormat::Glb || format == MeshFormat::GltfZip;
}

/// Loads a whole mesh file from memory with the real loader (tinyobjloader; tinygltf for .glb, and
/// for a .zip's .gltf with its files, gltf/gltf_zip.h) and
/// checks every vertex and index. Opens no file (no mtllib, no external glTF buffer or image URI).
/// Throws InputError at `path`, its message naming `name` and the line (OBJ, "line 12: ...") or
/// the glTF object ("accessor 3: ...", "buffer 0: ...") at fault: truncated, binary garbage,
/// NaN/infinite vertex, index out of range, no triangles.
///
/// With `texcoords` (for a textured material) an OBJ's texture coordinates are kept too.
///
/// A .glb gives the meshes of every node of every scene (all root nodes when it has no scene),
/// each under its node's world transform and then `transform`; materials are ignored. Nodes may
/// instance one mesh many times, so the instanced total is bounded (kMaxGlbElements). Limits hold
/// before memory is spent on a file (a service's limit on an upload): an OBJ's triangles and
/// vertices are counted by the line pass, a .glb's as its nodes are walked; over `maxTriangles`
/// triangles, or kMaxVerticesPerTriangle times that in vertices, it fails with MeshOverLimit at the
/// line or node that passes it.
/// Thread-safe.
TriangleMesh parseMeshBytes(std::string_view bytes, MeshFormat format,
                            const MeshTransform& transform, const std::string& name,
                            const std::string& path, uint64_t maxTriangles = uint64_t(1) << 25,
                            bool texcoords = false);

/// The InputError of a mesh file over parseMeshBytes' `maxTriangles`: a limit, which a service
/// answers as one, rather than a malformed file.
class MeshOverLimit : public InputError {
public:
    using InputError::InputError;
};

/// The most vertices plus triangles a .glb may make once its nodes have instanced their meshes
/// (about 400 MB of mesh): a file of a few kilobytes must not expand into gigabytes.
inline constexpr uint64_t kMaxGlbElements = uint64_t(1) << 25;
/// The most vertices (positions, normals or texture coordinates) a mesh file may have for each
/// triangle of its limit: as many as its triangles' corners, all unshared. More could not all be
/// used, and would only take memory.
inline constexpr uint64_t kMaxVerticesPerTriangle = 3;
/// The largest JSON chunk of a .glb read, and the most objects of one kind (nodes, meshes,
/// accessors, ...) in it: tinygltf keeps each in a few hundred bytes.
inline constexpr size_t kMaxGlbJsonBytes = size_t(16) << 20;
inline constexpr size_t kMaxGlbObjects = size_t(1) << 16;
/// The most corners of one OBJ face: tinyobjloader triangulates a polygon by ear clipping, which
/// takes time quadratic in its corners (one face of 10^6 corners, 7 MB, would take hours).
inline constexpr size_t kMaxObjFaceCorners = 256;

struct MeshBounds {
    Vec3 min, max;
};
/// The axis-aligned box of the mesh's positions (all of them, referenced or not); min > max for a
/// mesh without positions.
MeshBounds boundsOf(const TriangleMesh& mesh);

}  // namespace caustic
