// The OpenAPI 3 document of the API (server/http/openapi.json, embedded at build time).
#pragma once

#include <string>

namespace caustic::server {

const std::string& openApiDocument();

}  // namespace caustic::server
