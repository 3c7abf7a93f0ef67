#include "http/routes.h"

#include "http/access_log.h"
#include "http/guards.h"

namespace caustic::server {

void registerRoutes(httplib::Server& http, ApiContext& api) {
    http.set_payload_max_length(api.config.limits.maxRequestBytes);
    installGuards(http, api.config);
    installAccessLog(http);
    registerHealthRoutes(http, api);
    registerSceneRoutes(http, api);
    registerJobRoutes(http, api);
    // Static files of the web page, from its folder only.
    if (!api.config.webDir.empty()) http.set_mount_point("/", api.config.webDir.string());
}

}  // namespace caustic::server
