// The service's logs, through spdlog (docs/operations.md, "Logs and the access log"): its messages
// (start, stop, warnings, errors) go to stderr; the access log, one line per request
// (http/access_log.h), goes with them or where --access-log says.
#pragma once

#include <string>

namespace caustic::server {

/// The levels --log-level takes, spdlog's names, lowest first.
inline constexpr const char* kLogLevels[] = {"trace", "debug",    "info", "warning",
                                             "error", "critical", "off"};

/// Sends messages at `level` (one of kLogLevels) and above to stderr, and the access log (its
/// lines are at level info) to `accessLog`: empty for stderr, "-" for stdout, else a file,
/// appended to. Throws spdlog::spdlog_ex when the file cannot be opened. Call once, before
/// any thread logs.
void setUpLogging(const std::string& level, const std::string& accessLog);

}  // namespace caustic::server
