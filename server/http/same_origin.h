// The rules against other web sites (docs/security.md): a page on any site the user visits can
// make the browser send requests to 127.0.0.1:8080, and DNS rebinding can make a name of the
// attacker's resolve to 127.0.0.1, so that the browser takes the service for that site's own.
// These checks refuse what a browser sends on behalf of another site: a Host that is not a
// loopback name while the service listens on loopback, and a state change from an origin other
// than the service's own or one given with --allow-origin. Thread-safe (they only read).
#pragma once

#include <optional>
#include <string_view>

#include <httplib.h>

#include "http/problem.h"
#include "server_config.h"

namespace caustic::server {

/// Whether `host` (an address or name to listen on, "::1" without brackets) is a loopback one:
/// "localhost", 127.0.0.0/8 or ::1.
bool isLoopbackHost(std::string_view host);

/// The Host rules: 400 for an HTTP/1.1 request without Host (RFC 9112, section 3.2); while the
/// service listens on loopback, 403 for a Host (port optional) other than localhost, 127.x.x.x
/// or [::1].
std::optional<Refusal> checkHost(const ServerConfig& config, const httplib::Request& req);

/// For a request that changes state (POST, PUT, PATCH, DELETE): 403 when it carries an Origin
/// that is neither the service's own ("http://" and the request's Host) nor one of
/// config.allowedOrigins. A request without Origin (curl, scripts) passes.
std::optional<Refusal> checkOrigin(const ServerConfig& config, const httplib::Request& req);

/// Lets a page of an origin given with --allow-origin read the response to `req`
/// (Access-Control-Allow-Origin naming that origin, never "*"); does nothing for other requests.
void allowListedOrigin(const ServerConfig& config, const httplib::Request& req,
                       httplib::Response& res);

/// Whether `req` is a CORS preflight: OPTIONS with Origin and Access-Control-Request-Method.
bool isPreflight(const httplib::Request& req);

/// Answers a preflight (204 with the methods and headers the API takes) for an origin given with
/// --allow-origin; refuses it (403) for any other.
std::optional<Refusal> answerPreflight(const ServerConfig& config, const httplib::Request& req,
                                       httplib::Response& res);

}  // namespace caustic::server
