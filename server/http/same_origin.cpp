#include "http/same_origin.h"

#include <arpa/inet.h>

#include <algorithm>
#include <string>

#include "http/ascii.h"

namespace caustic::server {
namespace {

bool isLoopbackIPv4(std::string_view address) {
    in_addr a{};
    // inet_pton takes only the dotted-decimal quad: "127.1" and "0x7f.0.0.1" are not addresses.
    return inet_pton(AF_INET, std::string(address).c_str(), &a) == 1 &&
           (ntohl(a.s_addr) >> 24) == 127;
}

bool isLoopbackIPv6(std::string_view address) {
    in6_addr a{};
    return inet_pton(AF_INET6, std::string(address).c_str(), &a) == 1 && IN6_IS_ADDR_LOOPBACK(&a);
}

// Only "localhost" itself: browsers resolve its subdomains (foo.localhost) to loopback too, but
// other clients ask DNS, which an attacker may answer; nothing here needs them.
bool isLocalhost(std::string_view name) {
    return asciiLower(name) == "localhost";
}

// Whether a Host value names this machine's loopback: "localhost", "127.0.0.1:8080", "[::1]:80".
// The port, when given, is one to five digits; which one is not checked (a rebinding attack
// sends the right one).
bool isLoopbackHostHeader(std::string_view value) {
    std::string_view name = value, port;
    const bool bracketed = value.starts_with('[');
    if (bracketed) {
        const size_t close = value.find(']');
        if (close == std::string_view::npos) return false;
        name = value.substr(1, close - 1);
        port = value.substr(close + 1);
    } else if (const size_t colon = value.find(':'); colon != std::string_view::npos) {
        name = value.substr(0, colon);
        port = value.substr(colon);
    }
    const bool portOk = port.empty() || (port.size() >= 2 && port.size() <= 6 && port[0] == ':' &&
                                         std::all_of(port.begin() + 1, port.end(),
                                                     [](char c) { return c >= '0' && c <= '9'; }));
    if (!portOk) return false;
    return bracketed ? isLoopbackIPv6(name) : isLocalhost(name) || isLoopbackIPv4(name);
}

bool isListed(const ServerConfig& config, const std::string& origin) {
    const std::string lower = asciiLower(origin);
    return std::any_of(config.allowedOrigins.begin(), config.allowedOrigins.end(),
                       [&lower](const std::string& o) { return asciiLower(o) == lower; });
}

}  // namespace

bool isLoopbackHost(std::string_view host) {
    return isLocalhost(host) || isLoopbackIPv4(host) || isLoopbackIPv6(host);
}

std::optional<Refusal> checkHost(const ServerConfig& config, const httplib::Request& req) {
    if (!req.has_header("Host")) {
        // HTTP/1.0 has no Host; no browser sends such a request, so it is no rebinding attack.
        if (req.version == "HTTP/1.0") return std::nullopt;
        return Refusal{400, "an HTTP/1.1 request needs a Host header"};
    }
    const std::string host = req.get_header_value("Host");
    if (!isLoopbackHost(config.host) || isLoopbackHostHeader(host)) return std::nullopt;
    return Refusal{403, "the Host \"" + host +
                            "\" is not this machine's loopback: a server listening on loopback "
                            "answers only localhost, 127.x.x.x and [::1] (another name that "
                            "leads here is DNS rebinding)"};
}

std::optional<Refusal> checkOrigin(const ServerConfig& config, const httplib::Request& req) {
    if (!req.has_header("Origin")) return std::nullopt;
    const std::string origin = req.get_header_value("Origin");
    // The browser's page of this service is served from it: its origin is the Host it asked.
    const std::string scheme = config.tls() ? "https://" : "http://";
    if (asciiLower(origin) == asciiLower(scheme + req.get_header_value("Host")) ||
        isListed(config, origin))
        return std::nullopt;
    return Refusal{403, req.method + " from the origin \"" + origin +
                            "\" is refused: only this server's own page, clients that send no "
                            "Origin, and origins given with --allow-origin may change jobs"};
}

void allowListedOrigin(const ServerConfig& config, const httplib::Request& req,
                       httplib::Response& res) {
    if (config.allowedOrigins.empty()) return;
    // Whether the response names an origin depends on the request's Origin: caches must know.
    res.set_header("Vary", "Origin");
    const std::string origin = req.get_header_value("Origin");
    if (origin.empty() || !isListed(config, origin)) return;
    res.set_header("Access-Control-Allow-Origin", origin);
    res.set_header("Access-Control-Expose-Headers", "Location, Retry-After");
}

bool isPreflight(const httplib::Request& req) {
    return req.method == "OPTIONS" && req.has_header("Origin") &&
           req.has_header("Access-Control-Request-Method");
}

std::optional<Refusal> answerPreflight(const ServerConfig& config, const httplib::Request& req,
                                       httplib::Response& res) {
    const std::string origin = req.get_header_value("Origin");
    if (!isListed(config, origin))
        return Refusal{403, "the origin \"" + origin +
                                "\" may not call this API from a page (it is not one given with "
                                "--allow-origin)"};
    // Fetch standard, "CORS protocol": the methods and request headers a page may use; a
    // browser keeps the answer for Max-Age seconds.
    res.status = 204;
    res.set_header("Access-Control-Allow-Methods", "GET, POST, DELETE");
    res.set_header("Access-Control-Allow-Headers", "Authorization, Content-Type, Idempotency-Key");
    res.set_header("Access-Control-Max-Age", "600");
    return std::nullopt;
}

}  // namespace caustic::server
