// What every request passes before a route sees it (DESIGN.md, "Service", security): a size limit
// that holds before a body is read, no NUL in a path, the rules against other web sites (a
// loopback Host, the Origin of a change, the media type of a body: http/same_origin.h,
// http/media_types.h), the bearer token on every change, and a problem+json body for every
// error, exceptions included.
#pragma once

#include <httplib.h>

#include "server_config.h"

namespace caustic::server {

/// Installs the pre-routing checks, the error handler and the exception handler.
void installGuards(httplib::Server& http, const ServerConfig& config);

}  // namespace caustic::server
