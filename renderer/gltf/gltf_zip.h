// A .zip holding a .gltf with its buffers and images, the way users upload a glTF that is not one
// binary file: read from memory by libzip, every entry's name confined to the archive (relative,
// no "..", no backslash or drive), and its sizes bounded before and while it is read, so that a
// zip bomb is refused and never expands in memory past the limits.
#pragma once

#include <cstdint>
#include <string_view>

#include "gltf/gltf_model.h"
#include "scene/mesh_file.h"

namespace caustic {

struct ZipLimits {
    uint64_t maxEntries = 1024;
    uint64_t maxEntryBytes = uint64_t(256) << 20;  ///< one file, uncompressed
    uint64_t maxTotalBytes = uint64_t(512) << 20;  ///< every file read, uncompressed
    /// Uncompressed over compressed bytes of an entry (deflate reaches about 1000 on zeros; real
    /// meshes and images rarely pass 20).
    uint64_t maxRatio = 200;
};

/// Reads the archive's one .gltf (at any depth; two are an error naming both) and the files its
/// URIs name, relative to it and inside the archive. Entries are checked from the central
/// directory first (count, names, declared sizes and ratios), then each file read is held to its
/// declared size and the limits whatever the directory says. Every refusal is an InputError naming
/// the entry (a 422 from the service).
GltfFile loadGltfZip(std::string_view bytes, const ZipLimits& limits, const MeshErrors& errors);

/// A model upload of either glTF format: a .glb (loadGlbModel) or a .zip (loadGltfZip, default
/// limits).
GltfFile loadGltfUpload(std::string_view bytes, MeshFormat format, const MeshErrors& errors);

}  // namespace caustic
