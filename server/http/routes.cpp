#include "http/routes.h"

#include <algorithm>

#include "http/access_log.h"
#include "http/guards.h"

namespace caustic::server {

void registerRoutes(httplib::Server& http, ApiContext& api) {
    // cpp-httplib has one limit for every route: the larger; guards hold each route to its own.
    http.set_payload_max_length(
        std::max(api.config.limits.maxRequestBytes, api.config.limits.maxAssetBytes));
    installGuards(http, api.config);
    installAccessLog(http);
    registerHealthRoutes(http, api);
    registerSceneRoutes(http, api);
    registerJobRoutes(http, api);
    registerAssetRoutes(http, api);
    registerFarmRoutes(http, api);
    // Static files of the web page, from its folder only.
    if (!api.config.webDir.empty()) http.set_mount_point("/", api.config.webDir.string());
    // The documentation the API links to (openapi.json's externalDocs), from its folder only.
    // Markdown is text (RFC 7763), which browsers show rather than download.
    if (!api.config.docsDir.empty()) {
        http.set_mount_point("/docs", api.config.docsDir.string());
        http.set_file_extension_and_mimetype_mapping("md", "text/markdown; charset=utf-8");
    }
}

}  // namespace caustic::server
