// An uploaded mesh as the service stores it (POST /api/assets): what the upload's validation found
// (format, counts, bounds) and when it was made and last used. The file's bytes are kept beside
// it in the store and read only when a job renders (JobStore::assetBytes).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace caustic::server {

struct Asset {
    std::string id;         ///< SHA-256 of the bytes, 64 lowercase hex digits.
    int64_t seq = 0;        ///< Upload order, assigned by the store (the list's cursor).
    std::string format;     ///< "obj" or "glb" (nameOf(MeshFormat)).
    std::string name;       ///< The uploader's display name; may be empty.
    int64_t bytes = 0;      ///< Size of the file.
    int64_t triangles = 0;  ///< As loaded (polygons triangulated).
    int64_t vertices = 0;   ///< Positions the loaded mesh keeps.
    std::array<double, 3> boundsMin{}, boundsMax{};  ///< Axis-aligned bounds, untransformed.
    double createdAt = 0;                            ///< Unix seconds.
    double lastUsedAt = 0;  ///< Unix seconds: the upload, or the last job admitted with it.
};

struct AssetPage {
    std::vector<Asset> assets;
    std::optional<int64_t> next;  ///< Cursor (a seq) for the next page, if there is one.
};

/// What storing an asset came to.
enum class AssetInsert {
    Inserted,  ///< New.
    Existing,  ///< The same bytes (the same id) were stored already: nothing changed but its use.
    Full,      ///< Storing it would pass the total size allowed: nothing was stored.
};

/// What removing an asset came to.
enum class AssetRemoval { Removed, Unknown, InUse };

}  // namespace caustic::server
