// The access log (docs/operations.md, "Logs and the access log"): one line per request, whatever
// answered it (a route, a guard, a static file, an error, an event stream once it ends), with the
// peer, method, path (no query, no body), status, response bytes ("-" for a streamed body) and
// milliseconds from routing to the end of the response ("-" for a request refused before routing, a
// malformed one), after spdlog's local date and time:
//   <date> <time> access 127.0.0.1:50312 GET /api/jobs 200 1234 0.4 ms
#pragma once

#include <httplib.h>

namespace caustic::server {

/// Writes a line per request to spdlog's "access" logger (server/logging.h), or its default
/// logger when there is none.
void installAccessLog(httplib::Server& http);

/// Marks the start of `req`, on the thread that serves it; the pre-routing handler calls it.
void markRequestStart(const httplib::Request& req);

}  // namespace caustic::server
