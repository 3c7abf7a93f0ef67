#include "http/routes.h"

#include "http/guards.h"

namespace caustic::server {

void registerRoutes(httplib::Server& http, ApiContext& api) {
    http.set_payload_max_length(api.config.limits.maxRequestBytes);
    installGuards(http, api.config);
    registerHealthRoutes(http, api);
    registerSceneRoutes(http, api);
    registerJobRoutes(http, api);
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
