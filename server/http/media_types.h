// What body each route takes, in one table (media_types.cpp): a page on another site can send a
// "simple" cross-site request without a preflight only as text/plain, a form or multipart
// (Fetch standard, "CORS-safelisted request-header"), so a body typed as anything but what the
// route takes is refused (415) before it is read.
#pragma once

#include <optional>

#include <httplib.h>

#include "http/problem.h"

namespace caustic::server {

/// 415 when `req` has a body (Content-Length over 0) and its route takes none, or the body's
/// Content-Type is missing or not one the route takes (parameters such as charset=utf-8 are
/// allowed; the type is case-insensitive). Thread-safe.
std::optional<Refusal> checkMediaType(const httplib::Request& req);

}  // namespace caustic::server
