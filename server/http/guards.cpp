#include "http/guards.h"

#include <algorithm>
#include <cctype>
#include <optional>
#include <string>

#include "http/access_log.h"
#include "http/connection_gate.h"
#include "http/media_types.h"
#include "http/problem.h"
#include "http/same_origin.h"
#include "store/storage_full.h"
#include "store/store_unavailable.h"

namespace caustic::server {
namespace {

bool mutating(const std::string& method) {
    return method == "POST" || method == "PUT" || method == "PATCH" || method == "DELETE";
}

// Compares without an early exit, so that timing does not tell how much of a token was right.
bool sameToken(const std::string& given, const std::string& token) {
    if (given.size() != token.size() || token.empty()) return false;
    unsigned char diff = 0;
    for (size_t i = 0; i < token.size(); ++i) diff |= uint8_t(given[i] ^ token[i]);
    return diff == 0;
}

// "Bearer <token>"; the scheme is case-insensitive (RFC 9110, section 11.1), the token is not.
bool authorized(const std::string& auth, const std::string& token) {
    const std::string prefix = "bearer ";
    return auth.size() >= prefix.size() &&
           std::equal(prefix.begin(), prefix.end(), auth.begin(),
                      [](char a, char b) { return a == std::tolower((unsigned char)b); }) &&
           sameToken(auth.substr(prefix.size()), token);
}

// The body size allowed on this route, or nothing when the declared Content-Length is within it. An
// uploaded mesh (POST /api/assets) may be far larger than a job: cpp-httplib's one payload limit is
// the larger of the two (http/routes.cpp), so each route's own holds here, before the body is read.
std::optional<std::string> oversizeBody(const ServiceLimits& limits, const httplib::Request& req) {
    const bool upload = req.method == "POST" && req.path == "/api/assets";
    const size_t limit = upload ? limits.maxAssetBytes : limits.maxRequestBytes;
    const uint64_t length = req.get_header_value<uint64_t>("Content-Length");
    if (length <= limit) return std::nullopt;
    return "the request body has " + std::to_string(length) + " bytes; this server takes at most " +
           std::to_string(limit) + (upload ? " (--max-asset-bytes)" : " (--max-request-bytes)");
}

httplib::Server::HandlerResponse checkRequest(const ServerConfig& config,
                                              const httplib::Request& req, httplib::Response& res) {
    // Answered here, before cpp-httplib reads the body: the client must close the connection, or
    // its next request on it would be read from the body left unread.
    auto refuse = [&res](int status, const std::string& detail) {
        res.set_header("Connection", "close");
        sendProblem(res, status, detail);
        return httplib::Server::HandlerResponse::Handled;
    };
    // A decoded %00 would cut a static file's name short ("/index.html%00.png").
    if (req.path.find('\0') != std::string::npos) return refuse(400, "the path has a NUL byte");
    // Another site's page (http/same_origin.h). A foreign Host first: after DNS rebinding the
    // page reads the answers, so reads are refused too.
    if (std::optional<Refusal> r = checkHost(config, req)) return refuse(r->status, r->detail);
    allowListedOrigin(config, req, res);
    // Only a Content-Length holds a body to --max-request-bytes: cpp-httplib reads chunked and
    // compressed bodies whole, whatever their size, and a POST with neither header until the
    // connection closes.
    if (req.has_header("Transfer-Encoding"))
        return refuse(411, "send the body with a Content-Length, not chunked");
    if (const std::string coding = req.get_header_value("Content-Encoding");
        !coding.empty() && coding != "identity")
        return refuse(415, "compressed bodies (Content-Encoding) are not accepted");
    // A request with neither header has no body (RFC 9112, section 6.3), as in
    // `curl -X POST .../cancel`. `req` is the server's own, not a const object.
    if (!req.has_header("Content-Length"))
        const_cast<httplib::Request&>(req).set_header("Content-Length", "0");
    if (std::optional<std::string> oversize = oversizeBody(config.limits, req))
        return refuse(413, *oversize);
    if (isPreflight(req)) {
        if (std::optional<Refusal> r = answerPreflight(config, req, res))
            return refuse(r->status, r->detail);
        return httplib::Server::HandlerResponse::Handled;
    }
    // The media type before the Origin: a form or a text/plain body is 415 whatever its Origin
    // (Firefox before version 70 sent none with a form).
    if (std::optional<Refusal> r = checkMediaType(req)) return refuse(r->status, r->detail);
    if (mutating(req.method))
        if (std::optional<Refusal> r = checkOrigin(config, req))
            return refuse(r->status, r->detail);

    if (config.token.empty() || !mutating(req.method) ||
        authorized(req.get_header_value("Authorization"), config.token))
        return httplib::Server::HandlerResponse::Unhandled;
    res.set_header("WWW-Authenticate", "Bearer");
    return refuse(401, "this server needs \"Authorization: Bearer <token>\" to change jobs");
}

}  // namespace

void installGuards(httplib::Server& http, const ServerConfig& config) {
    http.set_pre_routing_handler([&config](const httplib::Request& req, httplib::Response& res) {
        markRequestStart(req);
        ConnectionGate::headRead(req.get_header_value<uint64_t>("Content-Length"));
        return checkRequest(config, req, res);
    });
    // Every error without a body of its own (unknown routes, a body over the limit) gets one.
    http.set_error_handler([](const httplib::Request&, httplib::Response& res) {
        if (res.body.empty()) {
            std::string detail = res.status == 413   ? "the request body is over the size limit"
                                 : res.status == 404 ? "no such resource"
                                                     : statusTitle(res.status);
            sendProblem(res, res.status, detail);
        }
    });
    http.set_exception_handler(
        [](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
            std::string what = "internal error";
            try {
                std::rethrow_exception(ep);
            } catch (const StorageFull& e) {
                return sendProblem(res, 507, e.what());  // RFC 4918, section 11.5
            } catch (const StoreUnavailable& e) {
                // PostgreSQL restarting or out of reach: worth trying again shortly.
                res.set_header("Retry-After", "5");
                return sendProblem(res, 503, e.what());
            } catch (const std::exception& e) {
                what = std::string("internal error: ") + e.what();
            } catch (...) {
            }
            sendProblem(res, 500, what);
        });
}

}  // namespace caustic::server
