// The asset service (DESIGN.md, "Service", assets): the policy of POST/GET/DELETE /api/assets over
// the store. An upload is validated with the renderer's real loader (scene/mesh_file.h), named by
// the SHA-256 of its bytes (the same bytes twice are one asset), and held to the service's limits:
// bytes and triangles per asset, total storage, uploads at once. Route handlers (server/http/)
// only translate. Thread-safe: request threads call it at once.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "gltf/gltf_model.h"
#include "scene/mesh_file.h"
#include "scene/scene.h"
#include "server_config.h"
#include "store/job_store.h"

namespace caustic::server {

/// What an upload came to.
struct Upload {
    enum class Outcome {
        Created,           ///< Stored now: `asset`.
        Existing,          ///< The same bytes were stored before: `asset`, as stored then.
        UnsupportedType,   ///< Not model/obj, model/gltf-binary or application/zip.
        BadName,           ///< The display name is too long or not UTF-8.
        TooLarge,          ///< Over --max-asset-bytes.
        Invalid,           ///< The loader refused the file: `detail` names the line or object.
        TooManyTriangles,  ///< Over --max-asset-triangles.
        StorageFull,       ///< Over --max-asset-storage-mib, or the disk is full.
        Busy,              ///< --max-uploads are being validated already.
    };
    Outcome outcome = Outcome::Invalid;
    Asset asset;
    std::string detail;  ///< Why it was refused.
    Json model;          ///< A .glb's modelSummary; null for an OBJ.
};

/// One of the --max-uploads places, held from before an upload's body is read until it is stored.
class UploadSlot {
public:
    explicit UploadSlot(std::atomic<int>& inFlight) : inFlight_(inFlight) {}
    ~UploadSlot() { inFlight_.fetch_sub(1); }
    UploadSlot(const UploadSlot&) = delete;
    UploadSlot& operator=(const UploadSlot&) = delete;

private:
    std::atomic<int>& inFlight_;
};

class AssetService {
public:
    AssetService(const ServerConfig& config, JobStore& store);

    /// Before the body of an upload is read: refuses a wrong media type or name (UnsupportedType,
    /// BadName) or an upload over --max-uploads in flight (Busy); else holds a place in `slot`
    /// and returns nothing.
    std::optional<Upload> admit(std::string_view mediaType, const std::string& name,
                                std::unique_ptr<UploadSlot>& slot);
    /// Validates and stores the file `bytes` of an admitted upload.
    Upload upload(std::string_view mediaType, const std::string& name, const std::string& bytes);

    std::optional<Asset> get(const std::string& id) { return store_.getAsset(id); }
    /// What a glTF asset (.glb or .zip) holds as a scene (gltf/gltf_scene.h's summary: meshes,
    /// triangles, materials, textures with their sizes, cameras, lights, extensions, warnings);
    /// null for an OBJ. Kept from the upload or the first call (the id is the content's hash, so
    /// it never changes), else read from the store and imported counting only.
    Json model(const Asset& asset);
    AssetPage list(int limit, int64_t before) { return store_.listAssets(limit, before); }
    /// Removes an asset no queued or running job uses, and gives its space back to the disk.
    AssetRemoval remove(const std::string& id);

private:
    /// The refusal of a request whose type or name is wrong; nothing when they are right.
    std::optional<Upload> refuseRequest(std::string_view mediaType, const std::string& name) const;
    /// Loads the file and fills `asset` from the mesh; the refusal when it cannot be loaded or
    /// has too many triangles.
    std::optional<Upload> load(MeshFormat format, const std::string& name, const std::string& bytes,
                               Asset& asset, Json& model) const;
    /// The summary of a model imported as a scene, counting only; InputError when it does not
    /// import.
    Json modelSummary(const GltfFile& file, const MeshErrors& errors) const;

    /// Keeps a model's summary (at most kKeptModels of them: a GET then costs no import).
    void keep(const std::string& id, const Json& model);
    static constexpr size_t kKeptModels = 256;

    const ServerConfig& config_;
    JobStore& store_;
    std::atomic<int> inFlight_{0};
    std::mutex modelsMutex_;
    std::map<std::string, Json> models_;
};

/// Whether `id` has the form of an asset id: 64 lowercase hex digits.
bool isAssetId(std::string_view id);
/// SHA-256 of `bytes` as 64 lowercase hex digits (OpenSSL's EVP interface).
std::string sha256Hex(std::string_view bytes);

/// Resolves the "asset" shapes of a scene through `store` (SceneOptions::resolveMeshAsset): an
/// unknown id is an InputError at the shape's "asset" path. Reads the bytes only when asked,
/// each asset's once: make one resolver per scene load.
MeshAssetResolver storedAssets(JobStore& store);

}  // namespace caustic::server
