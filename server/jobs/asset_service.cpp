#include "jobs/asset_service.h"

#include <openssl/evp.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <map>
#include <memory>
#include <stdexcept>

#include "core/error.h"
#include "gltf/gltf_meshes.h"
#include "gltf/gltf_scene.h"
#include "gltf/gltf_zip.h"
#include "jobs/clock.h"
#include "scene/mesh_file.h"
#include "store/disk_space.h"
#include "store/storage_full.h"

namespace caustic::server {
namespace {

constexpr size_t kMaxNameCharacters = 200;

Upload refused(Upload::Outcome outcome, std::string detail) {
    Upload u;
    u.outcome = outcome;
    u.detail = std::move(detail);
    return u;
}

// Characters of UTF-8 text: every byte but the continuation bytes (10xxxxxx) starts one.
size_t characters(const std::string& s) {
    size_t n = 0;
    for (unsigned char c : s) n += (c & 0xc0) != 0x80;
    return n;
}

bool isUtf8(const std::string& s) {
    try {
        (void)Json(s).dump();
        return true;
    } catch (const Json::exception&) {
        return false;
    }
}

}  // namespace

bool isAssetId(std::string_view id) {
    if (id.size() != 64) return false;
    for (char c : id)
        if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
    return true;
}

std::string sha256Hex(std::string_view bytes) {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    if (EVP_Digest(bytes.data(), bytes.size(), digest, &length, EVP_sha256(), nullptr) != 1)
        throw std::runtime_error("OpenSSL could not compute a SHA-256");
    std::string hex;
    char byte[3];
    for (unsigned int i = 0; i < length; ++i) {
        std::snprintf(byte, sizeof byte, "%02x", digest[i]);
        hex += byte;
    }
    return hex;
}

AssetService::AssetService(const ServerConfig& config, JobStore& store)
    : config_(config), store_(store) {}

std::optional<Upload> AssetService::refuseRequest(std::string_view mediaType,
                                                  const std::string& name) const {
    using Outcome = Upload::Outcome;
    if (!meshFormatOfMediaType(mediaType))
        return refused(Outcome::UnsupportedType,
                       (mediaType.empty() ? std::string("no Content-Type")
                                          : "Content-Type \"" + std::string(mediaType) + "\"") +
                           ": send a mesh as model/obj or model/gltf-binary, or a glTF model "
                           "with its files as application/zip");
    if (!isUtf8(name)) return refused(Outcome::BadName, "name is not UTF-8");
    if (characters(name) > kMaxNameCharacters)
        return refused(Outcome::BadName,
                       "name is over " + std::to_string(kMaxNameCharacters) + " characters");
    return std::nullopt;
}

std::optional<Upload> AssetService::admit(std::string_view mediaType, const std::string& name,
                                          std::unique_ptr<UploadSlot>& slot) {
    if (std::optional<Upload> refusal = refuseRequest(mediaType, name)) return refusal;
    const int max = config_.limits.maxUploads;
    // Counted before the check, so that two uploads at once cannot both take the last place.
    if (inFlight_.fetch_add(1) >= max) {
        inFlight_.fetch_sub(1);
        return refused(
            Upload::Outcome::Busy,
            std::to_string(max) + " uploads are in progress already (--max-uploads); retry later");
    }
    slot = std::make_unique<UploadSlot>(inFlight_);
    return std::nullopt;
}

Json AssetService::modelSummary(const GltfFile& file, const MeshErrors& errors) const {
    GltfImportOptions options;
    options.countOnly = true;
    options.maxPixels = config_.limits.maxPixels;
    return importGltf(file, options, errors).summary;
}

void AssetService::keep(const std::string& id, const Json& model) {
    std::lock_guard lock(modelsMutex_);
    if (models_.size() >= kKeptModels) models_.erase(models_.begin());
    models_[id] = model;
}

Json AssetService::model(const Asset& asset) {
    const std::optional<MeshFormat> format = meshFormatNamed(asset.format);
    if (!format || !isGltfFormat(*format)) return nullptr;
    {
        std::lock_guard lock(modelsMutex_);
        if (auto it = models_.find(asset.id); it != models_.end()) return it->second;
    }
    std::shared_ptr<const std::string> bytes = store_.assetBytes(asset.id);
    if (!bytes) return nullptr;
    Json model;
    const std::string name = asset.name.empty() ? "asset " + asset.id : asset.name, path;
    const MeshErrors errors{name, path};
    try {
        model = modelSummary(loadGltfUpload(*bytes, *format, errors), errors);
    } catch (const InputError& e) {
        // Stored under other limits (a larger --max-pixels): it imported then, not now.
        model = Json{{"error", e.message()}};
    }
    keep(asset.id, model);
    return model;
}

std::optional<Upload> AssetService::load(MeshFormat format, const std::string& name,
                                         const std::string& bytes, Asset& asset,
                                         Json& model) const {
    using Outcome = Upload::Outcome;
    // Load it with the renderer's own loader: what passes here renders.
    const int64_t maxTriangles = config_.limits.maxAssetTriangles;
    auto tooMany = [maxTriangles](const std::string& what) {
        return refused(Outcome::TooManyTriangles,
                       what + "; this server takes at most " + std::to_string(maxTriangles) +
                           " triangles per asset (--max-asset-triangles)");
    };
    TriangleMesh mesh;
    const std::string label = name.empty() ? "the upload" : name, path;
    const MeshErrors errors{label, path};
    try {
        if (isGltfFormat(format)) {
            // Read once: its mesh is checked vertex by vertex, and the model must import as a
            // scene too (materials, images, extensions).
            const GltfFile file = loadGltfUpload(bytes, format, errors);
            mesh = joinedMesh(file.model, MeshTransform{}, false, errors, uint64_t(maxTriangles));
            model = modelSummary(file, errors);
        } else {
            // An OBJ's triangles and vertices are counted before they are built, a .glb's as its
            // nodes instance its meshes: the limit bounds the memory.
            mesh =
                parseMeshBytes(bytes, format, MeshTransform{}, label, path, uint64_t(maxTriangles));
        }
    } catch (const MeshOverLimit& e) {
        return tooMany(e.message());
    } catch (const InputError& e) {
        return refused(Outcome::Invalid, e.message());
    }
    if (int64_t(mesh.triangles.size()) > maxTriangles)
        return tooMany("the mesh has " + std::to_string(mesh.triangles.size()) + " triangles");
    const MeshBounds bounds = boundsOf(mesh);
    asset.format = nameOf(format);
    asset.name = name;
    asset.bytes = int64_t(bytes.size());
    asset.triangles = int64_t(mesh.triangles.size());
    asset.vertices = int64_t(mesh.positions.size());
    asset.boundsMin = {bounds.min.x, bounds.min.y, bounds.min.z};
    asset.boundsMax = {bounds.max.x, bounds.max.y, bounds.max.z};
    return std::nullopt;
}

Upload AssetService::upload(std::string_view mediaType, const std::string& name,
                            const std::string& bytes) {
    using Outcome = Upload::Outcome;
    if (std::optional<Upload> refusal = refuseRequest(mediaType, name)) return *refusal;
    if (bytes.size() > config_.limits.maxAssetBytes)
        return refused(Outcome::TooLarge, "the file has " + std::to_string(bytes.size()) +
                                              " bytes; this server takes at most " +
                                              std::to_string(config_.limits.maxAssetBytes) +
                                              " per asset (--max-asset-bytes)");

    // The same bytes were loaded when they were first stored: take that asset as it is.
    const double now = unixNow();
    Asset asset;
    Json model;
    asset.id = sha256Hex(bytes);
    const MeshFormat format = *meshFormatOfMediaType(mediaType);
    if (std::optional<Asset> stored = store_.getAsset(asset.id)) {
        // The bytes were loaded as the format they were stored as: the same bytes in another
        // format did not load as that one.
        if (stored->format != nameOf(format))
            return refused(Outcome::Invalid, "these bytes are stored as asset " + asset.id +
                                                 " in the " + stored->format + " format, not as " +
                                                 nameOf(format));
        asset = *stored;
        model = this->model(asset);
    } else {
        // SQLite writes a new asset twice (its write-ahead log, then the database file).
        if (std::optional<std::string> low = lowDiskSpace(
                config_.dataDir, config_.storage.minFreeMiB, 2 * bytes.size(), "this upload"))
            return refused(Outcome::StorageFull, *low);
        if (std::optional<Upload> refusal = load(format, name, bytes, asset, model))
            return *refusal;
        asset.createdAt = now;
    }
    asset.lastUsedAt = now;

    // Store it within the storage limit.
    const int64_t maxStorage = config_.limits.maxAssetStorageMiB << 20;
    AssetInsert stored;
    try {
        stored = store_.insertAsset(asset, bytes, maxStorage);
    } catch (const StorageFull& e) {
        return refused(Outcome::StorageFull, e.what());
    }
    if (stored == AssetInsert::Full)
        return refused(Outcome::StorageFull,
                       "the asset storage is full: " + std::to_string(store_.assetBytesTotal()) +
                           " of " + std::to_string(maxStorage) +
                           " bytes are used and this file has " + std::to_string(bytes.size()) +
                           " (delete assets, or raise --max-asset-storage-mib)");
    Upload u;
    u.outcome = stored == AssetInsert::Inserted ? Outcome::Created : Outcome::Existing;
    u.asset = asset;
    if (!model.is_null()) keep(asset.id, model);
    u.model = std::move(model);
    return u;
}

AssetRemoval AssetService::remove(const std::string& id) {
    AssetRemoval removed = store_.removeAsset(id);
    if (removed == AssetRemoval::Removed) {
        std::lock_guard lock(modelsMutex_);
        models_.erase(id);
    }
    // A deleted asset frees its space at once: a user clearing room on a full disk sees it.
    if (removed == AssetRemoval::Removed) {
        try {
            store_.reclaimSpace();
        } catch (const std::exception& e) {
            // The asset is gone either way; retention's next sweep tries again.
            spdlog::warn("reclaiming the space of asset {}: {}", id, e.what());
        }
    }
    return removed;
}

MeshAssetResolver storedAssets(JobStore& store) {
    // A scene may place one asset many times: its bytes are read from the store once per scene.
    auto read = std::make_shared<std::map<std::string, std::shared_ptr<const std::string>>>();
    return [&store, read](const std::string& id, const std::string& path, bool needBytes) {
        auto unknown = [&] {
            return InputError(path, "no asset " + id + "; upload the file with POST /api/assets");
        };
        std::optional<Asset> stored = store.getAsset(id);
        if (!stored) throw unknown();
        MeshAsset asset;
        asset.format = meshFormatNamed(stored->format).value_or(MeshFormat::Obj);
        asset.counts.vertices = uint64_t(stored->vertices);
        asset.counts.triangles = uint64_t(stored->triangles);
        // The store keeps no record of vertex normals: budgeted as if the mesh had them.
        asset.counts.normals = true;
        if (needBytes) {
            std::shared_ptr<const std::string>& bytes = (*read)[id];
            if (!bytes) bytes = store.assetBytes(id);
            if (!bytes) throw unknown();
            asset.bytes = bytes;
        }
        return asset;
    };
}

}  // namespace caustic::server
