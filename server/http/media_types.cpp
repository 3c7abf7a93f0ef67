#include "http/media_types.h"

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

#include "http/ascii.h"
#include "scene/mesh_file.h"

namespace caustic::server {
namespace {

struct BodyRoute {
    std::string_view method;
    std::string_view path;
    std::vector<std::string_view> mediaTypes;  ///< Lower case, without parameters.
};

// Every route that takes a body; every other request takes none (cancel, DELETE, GET).
const std::vector<BodyRoute> kBodyRoutes = {
    {.method = "POST", .path = "/api/jobs", .mediaTypes = {"application/json"}},
    {.method = "POST",
     .path = "/api/assets",
     .mediaTypes = {mediaTypeOf(MeshFormat::Obj), mediaTypeOf(MeshFormat::Glb),
                    mediaTypeOf(MeshFormat::GltfZip)}},
};

// The media type of a Content-Type value, without parameters or spaces, in lower case
// (RFC 9110, section 8.3.1): "Application/JSON; charset=utf-8" -> "application/json".
std::string mediaType(std::string_view contentType) {
    std::string_view type = contentType.substr(0, contentType.find(';'));
    const auto space = [](char c) { return c == ' ' || c == '\t'; };
    while (!type.empty() && space(type.front())) type.remove_prefix(1);
    while (!type.empty() && space(type.back())) type.remove_suffix(1);
    return asciiLower(type);
}

std::string listOf(const std::vector<std::string_view>& types) {
    std::string list;
    for (std::string_view t : types) list += (list.empty() ? "" : " or ") + std::string(t);
    return list;
}

// The types a page of another site may send without a preflight: an HTML form's and a "simple"
// fetch's (Fetch standard, "CORS-safelisted request-header").
bool simpleRequestType(const std::string& type) {
    return type == "application/x-www-form-urlencoded" || type == "multipart/form-data" ||
           type == "text/plain";
}

}  // namespace

std::optional<Refusal> checkMediaType(const httplib::Request& req) {
    const std::string route = req.method + " " + req.path;
    const auto takes = std::find_if(kBodyRoutes.begin(), kBodyRoutes.end(), [&](const auto& r) {
        return r.method == req.method && r.path == req.path;
    });
    // The guards set a missing Content-Length to 0; one that is not a number is not 0. An empty
    // body is refused only when it comes as a form or text: a fieldless form posted by another
    // site (with no Origin from an old browser) must not cancel a job.
    if (req.get_header_value("Content-Length") == "0") {
        const std::string given = mediaType(req.get_header_value("Content-Type"));
        if (!simpleRequestType(given) ||
            (takes != kBodyRoutes.end() &&
             std::find(takes->mediaTypes.begin(), takes->mediaTypes.end(), given) !=
                 takes->mediaTypes.end()))
            return std::nullopt;
        return Refusal{415, route + " is not taken from a form or as " + given};
    }
    if (takes == kBodyRoutes.end()) return Refusal{415, route + " takes no body"};
    const std::string types = listOf(takes->mediaTypes);
    if (!req.has_header("Content-Type"))
        return Refusal{415, route + " needs a Content-Type: it takes " + types};
    const std::string given = req.get_header_value("Content-Type");
    if (std::find(takes->mediaTypes.begin(), takes->mediaTypes.end(), mediaType(given)) ==
        takes->mediaTypes.end())
        return Refusal{415, route + " takes " + types + ", not \"" + given + "\""};
    return std::nullopt;
}

}  // namespace caustic::server
