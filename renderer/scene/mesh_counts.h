// Vertex and triangle counts of an OBJ file from a line scan that parses no number: what a
// service needs to estimate a mesh's memory when it admits a job, without loading the mesh
// (DESIGN.md, "Service": admission only validates and estimates from counts).
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <string>
#include <unordered_map>

namespace caustic {

struct MeshCounts {
    /// `v` lines: the positions loadObj keeps; with normals, a bound on the vertices it makes (one
    /// per face corner at most: an OBJ indexes positions and normals apart). A textured material
    /// keeps texture coordinates too, which the same bound covers (3 x triangles).
    uint64_t vertices = 0;
    uint64_t triangles = 0;  ///< Triangles of the `f` lines once triangulated.
    bool normals = false;    ///< Vertex normals (`vn` lines), a Vec3 a vertex more.
    bool texcoords = false;  ///< Texture coordinates (`vt` lines), kept for a textured material.
};

/// Counts the `v` lines and the triangles of the `f` lines of an OBJ file: a face of n corners
/// makes n - 2 triangles, as triangulation does (tinyobjloader's never makes more). Reads every
/// byte once and parses no number, so a malformed vertex is found only by loadObj. Throws
/// InputError at `path` when the file cannot be read or has no faces, as loadObj does.
MeshCounts countObj(const std::filesystem::path& file, const std::string& path);

/// countObj's results for files already scanned, keyed by canonical path and valid while the
/// file's size and modification time stay the same: an unchanged file costs one stat().
/// Thread-safe.
class MeshCountCache {
public:
    /// The counts of `file` (countObj's, scanning it when it is new or changed).
    MeshCounts counts(const std::filesystem::path& file, const std::string& path);
    /// Files scanned so far: one per cache miss.
    uint64_t scans() const { return scans_.load(); }

private:
    struct Entry {
        uintmax_t size = 0;
        std::filesystem::file_time_type modified;
        MeshCounts counts;
    };
    std::mutex mutex_;
    std::unordered_map<std::string, Entry> entries_;
    std::atomic<uint64_t> scans_{0};
};

}  // namespace caustic
