// The assets resource (uploaded meshes): POST /api/assets, GET /api/assets[/{id}], DELETE.
#include <algorithm>
#include <memory>
#include <string>

#include "http/problem.h"
#include "http/routes.h"

namespace caustic::server {
namespace {

// `model`: a .glb's scene summary (AssetService::model), null for an OBJ.
Json assetJson(const Asset& a, const Json& model = nullptr) {
    return {{"id", a.id},
            {"format", a.format},
            {"name", a.name},
            {"bytes", a.bytes},
            {"triangles", a.triangles},
            {"vertices", a.vertices},
            {"bounds", {{"min", a.boundsMin}, {"max", a.boundsMax}}},
            {"created_at", a.createdAt},
            {"model", model}};
}

void sendUpload(httplib::Response& res, const Upload& u) {
    using Outcome = Upload::Outcome;
    switch (u.outcome) {
        case Outcome::Created:
        case Outcome::Existing:
            res.set_header("Location", "/api/assets/" + u.asset.id);
            return sendJson(res, u.outcome == Outcome::Created ? 201 : 200,
                            assetJson(u.asset, u.model));
        case Outcome::UnsupportedType:
            return sendProblem(res, 415, u.detail);
        case Outcome::BadName:
            return sendProblem(res, 400, u.detail);
        case Outcome::TooLarge:
            return sendProblem(res, 413, u.detail);
        case Outcome::Invalid:
        case Outcome::TooManyTriangles:
            return sendProblem(res, 422, u.detail);
        case Outcome::StorageFull:
            return sendProblem(res, 507, u.detail);
        case Outcome::Busy:
            res.set_header("Retry-After", "5");
            return sendProblem(res, 429, u.detail);
    }
}

// Reads and drops the body of a refused upload, so that the connection can carry the next request
// (its size was held to --max-asset-bytes from the Content-Length before this).
void dropBody(const httplib::Request& req, const httplib::ContentReader& read) {
    auto drop = [](const char*, size_t) { return true; };
    if (req.is_multipart_form_data())
        read([](const httplib::MultipartFormData&) { return true; }, drop);
    else
        read(drop);
}

// Refusals that need no body come before it is read: an upload holds its --max-uploads place
// from here, while its body arrives, until it is stored.
void uploadAsset(ApiContext& api, const httplib::Request& req, httplib::Response& res,
                 const httplib::ContentReader& read) {
    const std::string mediaType = req.get_header_value("Content-Type");
    const std::string name = req.get_param_value("name");
    std::unique_ptr<UploadSlot> slot;
    if (std::optional<Upload> refusal = api.assets.admit(mediaType, name, slot)) {
        dropBody(req, read);
        return sendUpload(res, *refusal);
    }
    // The buffer grows as bytes arrive, doubling up to the declared length: a client that declares
    // 256 MiB and sends nothing holds no memory for it.
    const size_t declared = std::min(req.get_header_value<uint64_t>("Content-Length"),
                                     uint64_t(api.config.limits.maxAssetBytes));
    std::string body;
    read([&body, declared](const char* data, size_t n) {
        if (body.size() + n > body.capacity())
            body.reserve(std::max(body.size() + n, std::min(2 * body.capacity(), declared)));
        body.append(data, n);
        return true;
    });
    sendUpload(res, api.assets.upload(mediaType, name, body));
}

void listAssets(ApiContext& api, const httplib::Request& req, httplib::Response& res) {
    std::optional<int64_t> limit = integerParam(req, res, "limit", 1, 100, 20);
    if (!limit) return;
    std::optional<int64_t> cursor = integerParam(req, res, "cursor", 1, INT64_MAX, INT64_MAX);
    if (!cursor) return;
    AssetPage page = api.assets.list(int(*limit), *cursor);
    Json assets = Json::array();
    for (const Asset& a : page.assets) assets.push_back(assetJson(a));
    sendJson(res, 200,
             {{"assets", assets}, {"next_cursor", page.next ? Json(*page.next) : Json(nullptr)}});
}

// The id of an asset route; answers 404 and returns nothing when there is no such asset id.
std::optional<std::string> assetId(const httplib::Request& req, httplib::Response& res) {
    const std::string id = req.matches[1];
    if (isAssetId(id)) return id;
    sendProblem(res, 404,
                "no asset \"" + id +
                    "\": an asset id is the SHA-256 of its bytes, 64 lowercase "
                    "hex digits");
    return std::nullopt;
}

void deleteAsset(ApiContext& api, const httplib::Request& req, httplib::Response& res) {
    std::optional<std::string> id = assetId(req, res);
    if (!id) return;
    switch (api.assets.remove(*id)) {
        case AssetRemoval::Removed:
            res.status = 204;
            return;
        case AssetRemoval::Unknown:
            return sendProblem(res, 404, "no asset " + *id);
        case AssetRemoval::InUse:
            return sendProblem(res, 409,
                               "asset " + *id +
                                   " is used by a queued or running job; delete or cancel the "
                                   "job first");
    }
}

}  // namespace

void registerAssetRoutes(httplib::Server& http, ApiContext& api) {
    using Req = const httplib::Request&;
    using Res = httplib::Response&;
    const std::string asset = "/api/assets/([^/]+)";
    http.Post("/api/assets", [&api](Req req, Res res, const httplib::ContentReader& read) {
        uploadAsset(api, req, res, read);
    });
    http.Get("/api/assets", [&api](Req req, Res res) { listAssets(api, req, res); });
    http.Get(asset, [&api](Req req, Res res) {
        std::optional<std::string> id = assetId(req, res);
        if (!id) return;
        if (std::optional<Asset> a = api.assets.get(*id))
            return sendJson(res, 200, assetJson(*a, api.assets.model(*a)));
        sendProblem(res, 404, "no asset " + *id);
    });
    http.Delete(asset, [&api](Req req, Res res) { deleteAsset(api, req, res); });
}

}  // namespace caustic::server
