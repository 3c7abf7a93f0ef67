// OBJ meshes through tinyobjloader, confined to the assets folder.
#pragma once

#include <filesystem>
#include <istream>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/math.h"

namespace caustic {

struct TriangleMesh {
    std::vector<Vec3> positions;
    std::vector<glm::uvec3> triangles;  ///< Counter-clockwise index triples.
    /// Per position, when the file has them (else empty): unit vertex normals, already
    /// transformed.
    std::vector<Vec3> normals;
    /// Per position, when the file has them (else empty): texture coordinates (s, t), t running
    /// down the image as in glTF (an OBJ's `vt` v is flipped).
    std::vector<Vec2> texcoords;
};

/// Scale, then rotations about x, y and z in degrees, then translation.
struct MeshTransform {
    Vec3 scale{1.0f};
    Vec3 rotateDegrees{0.0f};
    Vec3 translate{0.0f};
    Vec3 apply(const Vec3& p) const;
    /// A normal under the same transform (the inverse transpose: the scale divides), unit length;
    /// zero for a zero normal.
    Vec3 applyToNormal(const Vec3& n) const;
};

/// Resolves `name` inside `assetsDir`: relative, no ".." component, no escape through links; it
/// must name an existing file. Throws InputError at `path` otherwise.
std::filesystem::path resolveAsset(const std::filesystem::path& assetsDir, const std::string& name,
                                   const std::string& path);

/// Loads an OBJ file's faces (polygons are triangulated) and applies `transform`, with the vertex
/// normals the file has and, with `texcoords` (for a textured material), its texture
/// coordinates. Throws InputError at `path` for unreadable files or files without faces. Opens no
/// other file: materials come from the scene, so `mtllib` lines are ignored (a name there could
/// lead out of the assets folder).
TriangleMesh loadObj(const std::filesystem::path& file, const MeshTransform& transform,
                     const std::string& path, bool texcoords = false);
/// The same from OBJ text in a stream; `name` stands for the file in messages.
TriangleMesh parseObj(std::istream& in, const std::string& name, const MeshTransform& transform,
                      const std::string& path, bool texcoords = false);

}  // namespace caustic
