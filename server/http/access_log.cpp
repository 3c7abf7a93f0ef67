#include "http/access_log.h"

#include "http/connection_gate.h"

#include <chrono>
#include <string>

#include <spdlog/spdlog.h>

namespace caustic::server {
namespace {

using Clock = std::chrono::steady_clock;

// cpp-httplib reads, routes, answers and logs a request on one thread, and has no hook before
// routing but the pre-routing handler: the start is kept per thread, with the request it is of.
struct RequestStart {
    const httplib::Request* request = nullptr;
    Clock::time_point time;
};
thread_local RequestStart requestStart;

// A path as one field of the line: bytes that could forge a line or split the field (control
// characters, spaces, anything not ASCII; the path is percent-decoded) become \xNN.
std::string escaped(const std::string& path) {
    if (path.empty()) return "-";
    std::string out;
    for (unsigned char c : path) {
        if (c > 0x20 && c < 0x7f && c != '\\') {
            out += char(c);
        } else {
            constexpr char hex[] = "0123456789abcdef";
            out += {'\\', 'x', hex[c >> 4], hex[c & 15]};
        }
    }
    return out;
}

std::string peerOf(const httplib::Request& req) {
    if (req.remote_addr.empty()) return "-";
    const bool ipv6 = req.remote_addr.find(':') != std::string::npos;
    return (ipv6 ? "[" + req.remote_addr + "]" : req.remote_addr) + ":" +
           std::to_string(req.remote_port);
}

// The bytes of the body sent: a streamed (chunked) body's are not known here.
std::string bytesOf(const httplib::Response& res) {
    if (res.is_chunked_content_provider_) return "-";
    return std::to_string(res.content_provider_ ? res.content_length_ : res.body.size());
}

}  // namespace

void markRequestStart(const httplib::Request& req) {
    requestStart = {&req, Clock::now()};
}

void installAccessLog(httplib::Server& http) {
    std::shared_ptr<spdlog::logger> log = spdlog::get("access");
    if (!log) log = spdlog::default_logger();
    http.set_logger([log](const httplib::Request& req, const httplib::Response& res) {
        std::string ms = "-";
        if (requestStart.request == &req)
            ms = fmt::format("{:.1f}", std::chrono::duration<double, std::milli>(Clock::now() -
                                                                                 requestStart.time)
                                           .count());
        requestStart = {};
        // The logger is cpp-httplib's one hook after a response is written.
        ConnectionGate::responded();
        log->info("{} {} {} {} {} {} ms", peerOf(req), req.method.empty() ? "-" : req.method,
                  escaped(req.path), res.status, bytesOf(res), ms);
    });
}

}  // namespace caustic::server
